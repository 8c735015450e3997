#include "view/file_watcher.h"

#include <fstream>
#include <iterator>

namespace whitted {

FileWatcher::FileWatcher(std::filesystem::path path, std::chrono::milliseconds interval)
    : path_(std::move(path)), interval_(interval), lastLook_(std::chrono::steady_clock::now()) {
    std::ifstream in(path_, std::ios::binary);
    last_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::optional<std::string> FileWatcher::poll() {
    auto now = std::chrono::steady_clock::now();
    if (now - lastLook_ < interval_) return std::nullopt;
    lastLook_ = now;
    std::error_code timeError, sizeError;
    auto written = std::filesystem::last_write_time(path_, timeError);
    auto size = std::filesystem::file_size(path_, sizeError);
    if (timeError || sizeError) return std::nullopt;  // being replaced; look again next time
    if (written == lastWrite_ && size == lastSize_) return std::nullopt;
    std::ifstream in(path_, std::ios::binary);
    if (!in) return std::nullopt;  // being replaced; look again next time
    lastWrite_ = written;
    lastSize_ = size;
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text == last_) return std::nullopt;
    last_ = text;
    return text;
}

}  // namespace whitted
