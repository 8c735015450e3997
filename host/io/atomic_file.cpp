#include "io/atomic_file.h"

#include <fstream>
#include <stdexcept>

namespace whitted {

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
    std::filesystem::path temporary = path.parent_path() / ("." + path.filename().string() + ".partial");
    {
        std::ofstream out(temporary, std::ios::binary);
        out << text;
        if (!out.flush()) throw std::runtime_error(path.string() + ": cannot write file");
    }
    std::filesystem::rename(temporary, path);
}

}  // namespace whitted
