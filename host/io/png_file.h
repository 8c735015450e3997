// 8-bit PNG files written through libpng, without the image module
// (host/io/image_library.h): the bytes OpenImageIO 2.4's PNG writer gives
// for the same pixels and spec, so that a render into PNG need not load
// OpenImageIO's hundreds of libraries (tools/benchmark_results/README.md).
#pragma once

#include "io/image_library.h"

#include <memory>
#include <string>

namespace whitted {

// A writer for an 8-bit image of 1 to 4 channels (grey, grey and alpha,
// RGB, RGBA) into `path`, rows streamed from the top as they come; or null
// with `error` set. Nothing throws; libpng's errors come back as `error`.
std::unique_ptr<ImageFileWriter> openPngWriter(const std::string& path, const ImageFileSpec& spec,
                                               std::string& error);

}  // namespace whitted
