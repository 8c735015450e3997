// The one error of refused scene input, placed at its file and line: what
// the XML reader (scene/xml_reader.h) and the scene loader throw.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace whitted {

// "FILE:LINE: message"; when no line applies (line 0) "FILE: message".
inline std::string located(const std::string& file, int line, const std::string& message) {
    if (line > 0) return file + ":" + std::to_string(line) + ": " + message;
    return file + ": " + message;
}

// Any refused input. what() is "FILE:LINE: message"; when no line applies
// (line 0: the file cannot be read, or an XML error without a position) it
// is "FILE: message".
class SceneError : public std::runtime_error {
public:
    SceneError(std::string file, int line, std::string message)
        : std::runtime_error(located(file, line, message)),
          file_(std::move(file)),
          line_(line),
          message_(std::move(message)) {}
    const std::string& file() const { return file_; }
    int line() const { return line_; }
    const std::string& message() const { return message_; }

private:
    std::string file_;
    int line_;
    std::string message_;
};

}  // namespace whitted
