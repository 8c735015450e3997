// Reading an <environment> element (scene/environment.h) for the scene loader.
#pragma once

#include "scene/environment.h"
#include "scene/xml_reader.h"

#include <filesystem>

namespace whitted {

// Reads an <environment> element; a relative image path is relative to
// `folder`. Refuses bad input through `diag` at the element at fault.
Environment readEnvironment(const xml::Diagnostics& diag, const xml::XMLElement* e,
                            const std::filesystem::path& folder);

}  // namespace whitted
