#include "io/Ply.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "io/FormatError.h"

namespace ambler::io {

namespace {

constexpr std::uint64_t kMaxElements = 200'000'000;
constexpr std::size_t kMaxProperties = 256;
constexpr std::size_t kMaxHeaderLines = 1024;

enum class Encoding { kAscii, kLittle, kBig };

// A scalar type's size in bytes, or 0 for an unknown name.
int typeSize(const std::string& t) {
  static const std::map<std::string, int> sizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}

bool isFloat(const std::string& t) {
  return t == "float" || t == "float32" || t == "double" || t == "float64";
}
bool isUnsigned(const std::string& t) { return t[0] == 'u'; }

struct Property {
  std::string name;
  std::string type;        // the value's type
  std::string count_type;  // a list's count type; empty for a scalar
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

class Reader {
 public:
  explicit Reader(const std::filesystem::path& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw FormatError(path_.string() + ": PLY " + problem);
  }

  void readHeader(std::istream& in) {
    std::string line;
    if (!std::getline(in, line) || line != "ply") fail("file does not start with 'ply'");
    for (std::size_t n = 0; n < kMaxHeaderLines; ++n) {
      if (!std::getline(in, line)) fail("header ends before end_header");
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::istringstream words(line);
      std::string key;
      words >> key;
      if (key == "end_header") return checkHeader();
      if (key == "comment" || key == "obj_info" || key.empty()) continue;
      if (key == "format")
        format(words);
      else if (key == "element")
        element(words);
      else if (key == "property")
        property(words);
      else
        fail("unknown header line '" + line.substr(0, 40) + "'");
    }
    fail("header has no end_header in its first 1024 lines");
  }

  PlyMesh readBody(std::istream& in) {
    PlyMesh mesh;
    for (const auto& e : elements_)
      for (std::uint64_t i = 0; i < e.count; ++i) readItem(in, e, i, mesh);
    if (encoding_ == Encoding::kAscii) {
      std::string rest;
      if (in >> rest) fail("has more values than its elements need");
    } else if (in.peek() != std::char_traits<char>::eof()) {
      fail("has bytes after its last element");
    }
    for (const auto& t : mesh.triangles)
      for (const auto v : t)
        if (v < 0 || std::uint64_t(v) >= mesh.vertices.size())
          fail("a face names vertex " + std::to_string(v) + " of " +
               std::to_string(mesh.vertices.size()));
    return mesh;
  }

 private:
  void format(std::istringstream& words) {
    std::string name, version, extra;
    words >> name >> version;
    if (version != "1.0" || (words >> extra)) fail("format line is not '<encoding> 1.0'");
    if (name == "ascii")
      encoding_ = Encoding::kAscii;
    else if (name == "binary_little_endian")
      encoding_ = Encoding::kLittle;
    else if (name == "binary_big_endian")
      encoding_ = Encoding::kBig;
    else
      fail("format '" + name.substr(0, 40) + "' is not ascii or binary");
    has_format_ = true;
  }

  void element(std::istringstream& words) {
    Element e;
    std::string count, extra;
    words >> e.name >> count;
    const auto [ptr, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
    if (e.name.empty() || count.empty() || ec != std::errc() ||
        ptr != count.data() + count.size() || (words >> extra))
      fail("element line is not 'element <name> <count>'");
    if (e.count > kMaxElements) fail("element " + e.name + " has more than 200000000 items");
    if (std::any_of(elements_.begin(), elements_.end(),
                    [&](const Element& o) { return o.name == e.name; }))
      fail("element " + e.name + " is declared twice");
    elements_.push_back(e);
  }

  void property(std::istringstream& words) {
    if (elements_.empty()) fail("property before any element");
    auto& props = elements_.back().properties;
    if (props.size() == kMaxProperties) fail("an element has more than 256 properties");
    Property p;
    std::string first, extra;
    words >> first;
    if (first == "list")
      words >> p.count_type >> p.type >> p.name;
    else
      p.type = first, words >> p.name;
    if (p.name.empty() || (words >> extra) || typeSize(p.type) == 0 ||
        (first == "list" && (typeSize(p.count_type) == 0 || isFloat(p.count_type))))
      fail(
          "property line is not 'property <type> <name>' or 'property list <count type> "
          "<type> <name>' with PLY's types");
    props.push_back(p);
  }

  void checkHeader() {
    if (!has_format_) fail("header has no format line");
    for (const auto& e : elements_)
      if (e.properties.empty() && e.count > 0)
        fail("element " + e.name + " has items but no properties");
    const Element* vertex = find("vertex");
    const Element* face = find("face");
    if (!vertex || !face) fail("has no vertex or no face element");
    for (const char* axis : {"x", "y", "z"}) {
      const auto it = std::find_if(vertex->properties.begin(), vertex->properties.end(),
                                   [&](const Property& p) { return p.name == axis; });
      if (it == vertex->properties.end() || !it->count_type.empty())
        fail(std::string("vertex has no scalar property ") + axis);
    }
    if (std::none_of(face->properties.begin(), face->properties.end(), isIndexList))
      fail("face has no list property vertex_indices");
  }

  static bool isIndexList(const Property& p) {
    return !p.count_type.empty() && !isFloat(p.type) &&
           (p.name == "vertex_indices" || p.name == "vertex_index");
  }

  const Element* find(const std::string& name) const {
    const auto it = std::find_if(elements_.begin(), elements_.end(),
                                 [&](const Element& e) { return e.name == name; });
    return it == elements_.end() ? nullptr : &*it;
  }

  void readItem(std::istream& in, const Element& e, std::uint64_t i, PlyMesh& mesh) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    std::array<double, 3> xyz{};
    for (const auto& p : e.properties) {
      if (p.count_type.empty()) {
        const double v = value(in, p.type, e, i);
        if (is_vertex && p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z')
          xyz[std::size_t(p.name[0] - 'x')] = v;
        continue;
      }
      const double n = value(in, p.count_type, e, i);
      if (n < 0 || n > 65536)
        fail(e.name + " " + std::to_string(i) + " has a list of " + std::to_string(n) + " items");
      std::vector<std::int64_t> items(static_cast<std::size_t>(n));
      for (auto& item : items) item = std::int64_t(value(in, p.type, e, i));
      if (is_face && isIndexList(p)) {
        if (items.size() != 3)
          fail("face " + std::to_string(i) + " is not a triangle (" + std::to_string(items.size()) +
               " vertices)");
        if (items[0] == items[1] || items[1] == items[2] || items[0] == items[2])
          fail("face " + std::to_string(i) + " names a vertex twice");
        mesh.triangles.push_back({items[0], items[1], items[2]});
      }
    }
    if (is_vertex) {
      if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
        fail("vertex " + std::to_string(i) + " is not finite");
      mesh.vertices.push_back(xyz);
    }
  }

  double value(std::istream& in, const std::string& type, const Element& e, std::uint64_t i) {
    auto truncated = [&] {
      fail("truncated in " + e.name + " " + std::to_string(i) + " of " + std::to_string(e.count));
    };
    if (encoding_ == Encoding::kAscii) {
      std::string token;
      if (!(in >> token)) truncated();
      double v = 0;
      const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
      if (ec != std::errc() || ptr != token.data() + token.size() ||
          (!isFloat(type) && v != std::floor(v)))
        fail("value '" + token.substr(0, 40) + "' in " + e.name + " " + std::to_string(i) +
             " is not a " + type);
      return v;
    }
    const int size = typeSize(type);
    unsigned char b[8];
    if (!in.read(reinterpret_cast<char*>(b), size)) truncated();
    if ((encoding_ == Encoding::kBig) == (std::endian::native == std::endian::little))
      std::reverse(b, b + size);
    auto as = [&b]<typename T>(T) {
      T v;
      std::memcpy(&v, b, sizeof v);
      return double(v);
    };
    if (isFloat(type)) return size == 4 ? as(float{}) : as(double{});
    if (isUnsigned(type))
      return size == 1 ? as(std::uint8_t{}) : size == 2 ? as(std::uint16_t{}) : as(std::uint32_t{});
    return size == 1 ? as(std::int8_t{}) : size == 2 ? as(std::int16_t{}) : as(std::int32_t{});
  }

  const std::filesystem::path& path_;
  Encoding encoding_ = Encoding::kAscii;
  bool has_format_ = false;
  std::vector<Element> elements_;
};

}  // namespace

PlyMesh readPly(const std::filesystem::path& path) {
  Reader reader(path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) reader.fail("file does not exist");
  std::ifstream in(path, std::ios::binary);
  reader.readHeader(in);
  return reader.readBody(in);
}

}  // namespace ambler::io
