// File helpers of the mbest executable. Outputs are written with mbest/core/atomic_file.h.
#pragma once

#include <string>

#include "mbest/core/result.h"

namespace mbest::app {

// Creates `dir` and its parents; the error names the folder.
Status make_dirs(const std::string& dir);

}  // namespace mbest::app
