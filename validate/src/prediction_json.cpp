#include "prediction_json.h"

#include <fstream>

namespace mbest::validate {

Result<nlohmann::json> read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open"};
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    return Error{path + ": not valid JSON (" + e.what() + ")"};
  }
  return j;
}

Result<std::vector<Polyline>> centerlines_from_json(const nlohmann::json& j,
                                                    const std::string& path) {
  if (!j.is_object() || !j.contains("dlos") || !j["dlos"].is_array())
    return Error{path + ": field \"dlos\" missing or not an array"};
  std::vector<Polyline> out;
  for (size_t i = 0; i < j["dlos"].size(); ++i) {
    const nlohmann::json& dlo = j["dlos"][i];
    const std::string field = path + ": dlos[" + std::to_string(i) + "]";
    if (!dlo.is_object() || !dlo.contains("centerline") || !dlo["centerline"].is_array())
      return Error{field + ".centerline missing or not an array"};
    Polyline line;
    for (const nlohmann::json& p : dlo["centerline"]) {
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        return Error{field + ".centerline: a point is not [x, y]"};
      line.points.emplace_back(p[0].get<double>(), p[1].get<double>());
    }
    if (dlo.contains("closed") && dlo["closed"].is_boolean()) line.closed = dlo["closed"];
    out.push_back(std::move(line));
  }
  return out;
}

Result<std::vector<DetectedCrossing>> crossings_from_json(const nlohmann::json& j,
                                                         const std::string& path) {
  if (!j.is_object() || !j.contains("crossings") || !j["crossings"].is_array())
    return Error{path + ": field \"crossings\" missing or not an array"};
  const auto is_label = [](const nlohmann::json& v) {
    return v.is_number_integer() && v.get<long long>() >= 1 && v.get<long long>() <= 65535;
  };
  std::vector<DetectedCrossing> out;
  for (size_t i = 0; i < j["crossings"].size(); ++i) {
    const nlohmann::json& c = j["crossings"][i];
    const std::string field = path + ": crossings[" + std::to_string(i) + "]";
    if (!c.is_object()) return Error{field + " is not an object"};
    const nlohmann::json* location = c.contains("location") ? &c["location"] : nullptr;
    if (!location || !location->is_array() || location->size() != 2 ||
        !(*location)[0].is_number() || !(*location)[1].is_number())
      return Error{field + ".location missing or not [x, y]"};
    if (!c.contains("angle_deg") || !c["angle_deg"].is_number())
      return Error{field + ".angle_deg missing or not a number"};
    const double angle = c["angle_deg"].get<double>();
    if (angle < 0 || angle > 90)
      return Error{field + ".angle_deg: " + std::to_string(angle) + " is outside [0, 90]"};
    const nlohmann::json* labels = c.contains("dlos_top_first") ? &c["dlos_top_first"] : nullptr;
    if (!labels || !labels->is_array() || labels->size() != 2 || !is_label((*labels)[0]) ||
        !is_label((*labels)[1]))
      return Error{field + ".dlos_top_first missing or not [top, under], two labels in 1..65535"};
    DetectedCrossing d;
    d.location = cv::Point2d((*location)[0].get<double>(), (*location)[1].get<double>());
    d.angle_deg = angle;
    d.top_label = (*labels)[0].get<int>();
    d.under_label = (*labels)[1].get<int>();
    out.push_back(d);
  }
  return out;
}

}  // namespace mbest::validate
