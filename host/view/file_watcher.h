// Notices when a file's contents change, by polling: a stat a few times a
// second is cheap, needs no inotify, and also catches editors that replace
// the file by renaming a new one over it. The file is read only when its
// modification time or size moved, and reported only when its bytes differ.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace whitted {

class FileWatcher {
public:
    FileWatcher(std::filesystem::path path, std::chrono::milliseconds interval);
    // The new contents when they differ from the last seen ones (and the
    // interval has passed since the last look); nullopt otherwise.
    std::optional<std::string> poll();
    // Takes `contents` as seen (after the program wrote the file itself).
    void markSeen(std::string contents) { last_ = std::move(contents); }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    std::chrono::milliseconds interval_;
    std::chrono::steady_clock::time_point lastLook_;
    std::string last_;
    // Modification time and size when last read; reading again is due when
    // either differs.
    std::filesystem::file_time_type lastWrite_{};
    std::uintmax_t lastSize_ = 0;
};

}  // namespace whitted
