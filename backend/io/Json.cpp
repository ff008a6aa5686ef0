#include "io/Json.h"

#include <cmath>
#include <fstream>

#include "io/ReplaceFile.h"

namespace ambler::io {

nlohmann::json readJsonFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw FormatError("JSON '" + path.string() + "': cannot open (missing or unreadable)");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw FormatError("JSON '" + path.string() + "': malformed at byte " + std::to_string(e.byte) +
                      ": " + e.what());
  } catch (const nlohmann::json::exception& e) {
    // e.g. a number too large for a double: out_of_range, not parse_error.
    throw FormatError("JSON '" + path.string() + "': unusable value: " + e.what());
  }
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value) {
  writeThenReplace(path, [&](const std::filesystem::path& partial) {
    std::ofstream out(partial);
    out << value.dump(2) << '\n';
    if (!out) throw FormatError("JSON '" + path.string() + "': write failed");
  });
}

JsonFields::JsonFields(const nlohmann::json& object, std::string context)
    : object_(object), context_(std::move(context)) {
  if (!object_.is_object()) throw FormatError(context_ + ": expected a JSON object");
}

void JsonFields::fail(const std::string& key, const std::string& problem) const {
  throw FormatError(context_ + ": key \"" + key + "\" " + problem);
}

bool JsonFields::has(const std::string& key) const { return object_.contains(key); }

const nlohmann::json& JsonFields::require(const std::string& key) const {
  const auto it = object_.find(key);
  if (it == object_.end()) fail(key, "is missing");
  return *it;
}

double JsonFields::number(const std::string& key) const {
  const auto& v = require(key);
  if (!v.is_number()) fail(key, "must be a number, found " + std::string(v.type_name()));
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(key, "must be finite");
  return d;
}

int JsonFields::integer(const std::string& key) const {
  const auto& v = require(key);
  if (!v.is_number_integer()) fail(key, "must be an integer, found " + v.dump());
  const auto i = v.get<long long>();
  if (i < -2147483647LL || i > 2147483647LL) fail(key, "is out of range");
  return int(i);
}

std::string JsonFields::string(const std::string& key) const {
  const auto& v = require(key);
  if (!v.is_string()) fail(key, "must be a string, found " + std::string(v.type_name()));
  return v.get<std::string>();
}

std::vector<double> JsonFields::numbers(const std::string& key, std::size_t expected) const {
  const auto& v = require(key);
  if (!v.is_array() || v.size() != expected)
    fail(key, "must be an array of " + std::to_string(expected) + " numbers");
  std::vector<double> out;
  out.reserve(expected);
  for (const auto& e : v) {
    if (!e.is_number()) fail(key, "must contain only numbers, found " + e.dump());
    out.push_back(e.get<double>());
    if (!std::isfinite(out.back())) fail(key, "must contain only finite numbers");
  }
  return out;
}

JsonFields JsonFields::object(const std::string& key) const {
  return JsonFields(require(key), context_ + "." + key);
}

nlohmann::json gridJson(const GridSpec& grid) {
  return {{"origin_x", grid.origin_x},
          {"origin_y", grid.origin_y},
          {"resolution", grid.resolution},
          {"rows", grid.rows},
          {"cols", grid.cols}};
}

GridSpec readGridPlacement(const JsonFields& fields) {
  GridSpec grid;
  grid.origin_x = fields.number("origin_x");
  grid.origin_y = fields.number("origin_y");
  grid.resolution = fields.number("resolution");
  if (grid.resolution <= 0.0) fields.fail("resolution", "must be positive");
  return grid;
}

}  // namespace ambler::io
