// Notices when a file's contents change, by polling: reading a small scene
// file a few times a second is cheap, needs no inotify, and also catches
// editors that replace the file by renaming a new one over it.
#pragma once

#include <chrono>
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
};

}  // namespace whitted
