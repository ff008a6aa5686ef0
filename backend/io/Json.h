#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/GridSpec.h"
#include "io/FormatError.h"

namespace ambler::io {

// Parses a JSON file; FormatError names the file and, for syntax errors, the
// byte where parsing stopped.
nlohmann::json readJsonFile(const std::filesystem::path& path);

// Writes pretty-printed JSON through a temporary file and a rename.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value);

// Typed, checked access to the members of one JSON object. Every failure
// throws FormatError saying which file, which key, and what was wrong.
class JsonFields {
 public:
  JsonFields(const nlohmann::json& object, std::string context);

  bool has(const std::string& key) const;
  double number(const std::string& key) const;  // finite
  int integer(const std::string& key) const;
  std::string string(const std::string& key) const;
  std::vector<double> numbers(const std::string& key, std::size_t expected_count) const;
  JsonFields object(const std::string& key) const;

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

 private:
  const nlohmann::json& require(const std::string& key) const;

  const nlohmann::json& object_;
  std::string context_;
};

// The grid keys shared by the project's raster headers (docs/formats.md):
// origin_x, origin_y, resolution, rows, cols.
nlohmann::json gridJson(const GridSpec& grid);
// Reads origin_x, origin_y and resolution (> 0); rows and cols stay 0 for
// headers that take them from the raster.
GridSpec readGridPlacement(const JsonFields& fields);

}  // namespace ambler::io
