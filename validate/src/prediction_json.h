// The per-image JSON `mbest detect` writes (app/detect_command.cpp), parsed once for every
// figure taken from it. Internal to mbest_validate: nlohmann::json stays out of the public
// headers, whose readers (read_predicted_centerlines, read_predicted_crossings) wrap these.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mbest/core/result.h"
#include "mbest/validate/centerline_error.h"
#include "mbest/validate/crossing_list.h"

namespace mbest::validate {

// Parses the file at `path`. Errors name the file.
Result<nlohmann::json> read_json_file(const std::string& path);

// The "dlos" and "crossings" fields of a parsed JSON (formats in centerline_error.h and
// crossing_list.h); `path` names the file in errors, which also name the field.
Result<std::vector<Polyline>> centerlines_from_json(const nlohmann::json& j,
                                                    const std::string& path);
Result<std::vector<DetectedCrossing>> crossings_from_json(const nlohmann::json& j,
                                                         const std::string& path);

}  // namespace mbest::validate
