#include "io/Pcd.h"

#include <pcl/io/lzf.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/FormatError.h"

namespace ambler::io {

namespace {

// Far beyond any scan this station handles; a header claiming more is
// corrupt, and trusting it would mean allocating it.
constexpr std::uint64_t kMaxPoints = 200'000'000;
constexpr std::size_t kMaxFields = 256;
constexpr int kMaxCount = 65536;
constexpr std::size_t kMaxHeaderLines = 64;
// LZF expands at most about 100-fold (a 3-byte back reference copies up to
// 264 bytes); a block claiming more is not LZF.
constexpr std::uint64_t kMaxLzfRatio = 100;

class Parser {
 public:
  explicit Parser(const std::filesystem::path& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw FormatError(path_.string() + ": PCD " + problem);
  }

  std::uint64_t whole(const std::string& token, const std::string& key, std::uint64_t max) const {
    std::uint64_t value = 0;
    const auto* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, value);
    if (token.empty() || ec != std::errc() || ptr != end)
      fail(key + " '" + printable(token) + "' is not a whole number");
    if (value > max) fail(key + " " + token + " is more than " + std::to_string(max));
    return value;
  }

  double real(const std::string& token, const std::string& key) const {
    double value = 0;
    const auto* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, value);
    if (token.empty() || ec != std::errc() || ptr != end)
      fail(key + " '" + printable(token) + "' is not a number");
    return value;
  }

  // A header value cut to a readable length, with bytes outside ASCII shown
  // as '?', for messages.
  static std::string printable(const std::string& s) {
    std::string out = s.substr(0, 40);
    for (auto& c : out)
      if (c < 0x20 || c > 0x7e) c = '?';
    return out;
  }

 private:
  const std::filesystem::path& path_;
};

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// The keywords in the order PCL writes them; optional ones may be left out.
struct Keyword {
  const char* name;
  bool optional;
};
constexpr std::array<Keyword, 10> kKeywords = {{{"VERSION", false},
                                                {"FIELDS", false},
                                                {"SIZE", false},
                                                {"TYPE", false},
                                                {"COUNT", true},
                                                {"WIDTH", false},
                                                {"HEIGHT", false},
                                                {"VIEWPOINT", true},
                                                {"POINTS", false},
                                                {"DATA", false}}};

class HeaderReader {
 public:
  HeaderReader(const Parser& p, PcdHeader& h) : p_(p), h_(h) {}

  // Takes one header line; true once DATA has been read.
  bool take(const std::vector<std::string>& w) {
    const std::string& key = w[0];
    const auto it = std::find_if(kKeywords.begin(), kKeywords.end(),
                                 [&](const Keyword& k) { return key == k.name; });
    if (it == kKeywords.end()) p_.fail("unknown header line '" + Parser::printable(key) + "'");
    const std::size_t index = std::size_t(it - kKeywords.begin());
    if (index < next_) p_.fail(key + " is repeated or out of order");
    for (std::size_t k = next_; k < index; ++k)
      if (!kKeywords[k].optional)
        p_.fail(std::string("no ") + kKeywords[k].name + " before " + key);
    next_ = index + 1;
    const std::vector<std::string> args(w.begin() + 1, w.end());
    if (args.empty()) p_.fail(key + " has no value");
    if (key == "VERSION") version(args);
    if (key == "FIELDS") fields(args);
    if (key == "SIZE") sizes(args);
    if (key == "TYPE") types(args);
    if (key == "COUNT") counts(args);
    if (key == "WIDTH") h_.width = single(args, key);
    if (key == "HEIGHT") h_.height = single(args, key);
    if (key == "VIEWPOINT") viewpoint(args);
    if (key == "POINTS") h_.points = single(args, key);
    if (key == "DATA") data(args);
    return key == "DATA";
  }

 private:
  std::uint64_t single(const std::vector<std::string>& args, const std::string& key) const {
    if (args.size() != 1) p_.fail(key + " takes one number, not " + std::to_string(args.size()));
    return p_.whole(args[0], key, kMaxPoints);
  }

  void version(const std::vector<std::string>& args) const {
    if (args.size() != 1 || (args[0] != "0.7" && args[0] != ".7"))
      p_.fail("VERSION '" + Parser::printable(args[0]) + "' is not 0.7");
  }

  void fields(const std::vector<std::string>& args) {
    if (args.size() > kMaxFields) p_.fail("FIELDS lists more than 256 entries");
    for (const auto& name : args) {
      if (name != "_" && h_.column(name) >= 0) p_.fail("field " + name + " is listed twice");
      h_.fields.push_back({name});
    }
  }

  void sameLength(const std::vector<std::string>& args, const std::string& key) const {
    if (args.size() != h_.fields.size())
      p_.fail(key + " lists " + std::to_string(args.size()) + " entries for " +
              std::to_string(h_.fields.size()) + " FIELDS");
  }

  void sizes(const std::vector<std::string>& args) {
    sameLength(args, "SIZE");
    for (std::size_t i = 0; i < args.size(); ++i) {
      const auto& t = args[i];
      if (t != "1" && t != "2" && t != "4" && t != "8")
        p_.fail("SIZE " + Parser::printable(t) + " is not 1, 2, 4 or 8");
      h_.fields[i].size = t[0] - '0';
    }
  }

  void types(const std::vector<std::string>& args) {
    sameLength(args, "TYPE");
    for (std::size_t i = 0; i < args.size(); ++i) {
      auto& f = h_.fields[i];
      if (args[i] != "I" && args[i] != "U" && args[i] != "F")
        p_.fail("TYPE " + Parser::printable(args[i]) + " is not I, U or F");
      f.type = args[i][0];
      if (f.type == 'F' && f.size != 4 && f.size != 8)
        p_.fail("field " + f.name + " is a float of " + std::to_string(f.size) + " bytes");
    }
  }

  void counts(const std::vector<std::string>& args) {
    sameLength(args, "COUNT");
    for (std::size_t i = 0; i < args.size(); ++i) {
      h_.fields[i].count = int(p_.whole(args[i], "COUNT", kMaxCount));
      if (h_.fields[i].count == 0) p_.fail("a COUNT is 0");
    }
  }

  void viewpoint(const std::vector<std::string>& args) {
    if (args.size() != 7)
      p_.fail("VIEWPOINT has " + std::to_string(args.size()) + " numbers, not 7");
    std::array<double, 7> v{};
    for (std::size_t i = 0; i < 7; ++i)
      if (!std::isfinite(v[i] = p_.real(args[i], "VIEWPOINT"))) p_.fail("VIEWPOINT is not finite");
    h_.viewpoint = v;
  }

  void data(const std::vector<std::string>& args) {
    if (args.size() != 1) p_.fail("DATA line has more than one word");
    h_.data = args[0];
    if (h_.data != "ascii" && h_.data != "binary" && h_.data != "binary_compressed")
      p_.fail("DATA '" + Parser::printable(h_.data) +
              "' is not ascii, binary or binary_compressed");
  }

  const Parser& p_;
  PcdHeader& h_;
  std::size_t next_ = 0;
};

void checkPoints(const Parser& p, const PcdHeader& h, bool require_xyz) {
  if (require_xyz)
    for (const char* axis : {"x", "y", "z"})
      if (h.column(axis) < 0) p.fail(std::string("has no field ") + axis);
  if (h.width == 0 || h.height == 0 || h.points == 0) p.fail("has no points");
  if (h.width * h.height != h.points)
    p.fail("WIDTH x HEIGHT (" + std::to_string(h.width) + " x " + std::to_string(h.height) +
           ") is not POINTS (" + std::to_string(h.points) + ")");
}

template <typename T>
double element(const char* bytes) {
  T v;
  std::memcpy(&v, bytes, sizeof v);
  return double(v);
}

double element(const PcdField& f, const char* bytes) {
  switch (f.type) {
    case 'F':
      return f.size == 4 ? element<float>(bytes) : element<double>(bytes);
    case 'I':
      switch (f.size) {
        case 1:
          return element<std::int8_t>(bytes);
        case 2:
          return element<std::int16_t>(bytes);
        case 4:
          return element<std::int32_t>(bytes);
        default:
          return element<std::int64_t>(bytes);
      }
    default:
      switch (f.size) {
        case 1:
          return element<std::uint8_t>(bytes);
        case 2:
          return element<std::uint16_t>(bytes);
        case 4:
          return element<std::uint32_t>(bytes);
        default:
          return element<std::uint64_t>(bytes);
      }
  }
}

// The range of a whole-number field's values, for checking ascii text.
bool fits(const PcdField& f, double v) {
  if (v != std::floor(v)) return false;
  const double bits = 8.0 * f.size;
  if (f.type == 'U') return v >= 0 && v < std::exp2(bits);
  return v >= -std::exp2(bits - 1) && v < std::exp2(bits - 1);
}

// Point-major bytes (binary) or field-major bytes (binary_compressed
// unpacked) to values.
void decode(PcdCloud& c, const std::string& bytes, std::size_t offset, bool field_major) {
  const auto& h = c.header;
  const std::size_t per_point = h.elementsPerPoint();
  const std::uint64_t point_bytes = h.pointBytes();
  c.values.resize(h.points * per_point);
  std::size_t column = 0, field_start = 0;
  for (const auto& f : h.fields) {
    for (std::uint64_t i = 0; i < h.points; ++i)
      for (int e = 0; e < f.count; ++e) {
        const std::size_t within = std::size_t(f.size) * std::size_t(e);
        const std::size_t at = field_major
                                   ? field_start + std::size_t(i * f.size * f.count) + within
                                   : std::size_t(i * point_bytes) + field_start + within;
        const double v = element(f, bytes.data() + offset + at);
        if (f.type == 'F' && !std::isfinite(v)) c.dense = false;
        c.values[i * per_point + column + std::size_t(e)] = v;
      }
    column += std::size_t(f.count);
    field_start += std::size_t(f.size * f.count) * (field_major ? h.points : 1);
  }
}

void readAscii(const Parser& p, PcdCloud& c, const std::string& text) {
  const auto& h = c.header;
  const std::size_t per_point = h.elementsPerPoint();
  c.values.reserve(std::min<std::uint64_t>(h.points * per_point, text.size()));
  std::istringstream lines(text);
  std::uint64_t point = 0;
  for (std::string line; std::getline(lines, line);) {
    const auto tokens = words(line);
    if (tokens.empty()) continue;
    if (point == h.points) p.fail("has more than " + std::to_string(h.points) + " points");
    if (tokens.size() != per_point)
      p.fail("point " + std::to_string(point) + " has " + std::to_string(tokens.size()) +
             " values, not " + std::to_string(per_point));
    std::size_t t = 0;
    for (const auto& f : h.fields)
      for (int e = 0; e < f.count; ++e, ++t) {
        const double v = p.real(tokens[t], "point " + std::to_string(point) + " " + f.name);
        if (f.type == 'F' && !std::isfinite(v)) c.dense = false;
        if (f.type != 'F' && !fits(f, v))
          p.fail("point " + std::to_string(point) + " " + f.name + " " +
                 Parser::printable(tokens[t]) + " is not " +
                 (f.type == 'U' ? "an unsigned" : "a signed") + " integer of " +
                 std::to_string(f.size) + " bytes");
        c.values.push_back(v);
      }
    ++point;
  }
  if (point != h.points)
    p.fail("truncated: " + std::to_string(point) + " of " + std::to_string(h.points) + " points");
}

void readBinary(const Parser& p, PcdCloud& c, const std::string& bytes) {
  const std::uint64_t needed = c.header.points * c.header.pointBytes();
  if (bytes.size() != needed)
    p.fail(std::string(bytes.size() < needed ? "truncated" : "too long") + ": " +
           std::to_string(c.header.points) + " points need " + std::to_string(needed) +
           " bytes, the file has " + std::to_string(bytes.size()) + " after its header");
  decode(c, bytes, 0, false);
}

void readCompressed(const Parser& p, PcdCloud& c, const std::string& bytes) {
  const std::uint64_t needed = c.header.points * c.header.pointBytes();
  std::uint32_t sizes[2] = {0, 0};
  if (bytes.size() < 8) p.fail("truncated: no compressed block sizes after the header");
  std::memcpy(sizes, bytes.data(), 8);
  if (sizes[0] != bytes.size() - 8)
    p.fail("the compressed block is " + std::to_string(sizes[0]) + " bytes, the file has " +
           std::to_string(bytes.size() - 8) + " after its sizes");
  if (sizes[1] != needed)
    p.fail("the compressed block unpacks to " + std::to_string(sizes[1]) + " bytes, not the " +
           std::to_string(needed) + " its points need");
  if (needed > kMaxLzfRatio * std::max<std::uint64_t>(sizes[0], 1))
    p.fail("a compressed block of " + std::to_string(sizes[0]) + " bytes cannot unpack to " +
           std::to_string(needed));
  std::string unpacked(needed, '\0');
  if (pcl::lzfDecompress(bytes.data() + 8, sizes[0], unpacked.data(), sizes[1]) != sizes[1])
    p.fail("the compressed block is corrupt");
  decode(c, unpacked, 0, true);
}

}  // namespace

std::uint64_t PcdHeader::pointBytes() const {
  std::uint64_t bytes = 0;
  for (const auto& f : fields) bytes += std::uint64_t(f.size) * std::uint64_t(f.count);
  return bytes;
}

std::size_t PcdHeader::elementsPerPoint() const {
  std::size_t n = 0;
  for (const auto& f : fields) n += std::size_t(f.count);
  return n;
}

int PcdHeader::column(const std::string& name) const {
  int column = 0;
  for (const auto& f : fields) {
    if (f.name == name) return column;
    column += f.count;
  }
  return -1;
}

PcdHeader readPcdHeader(const std::filesystem::path& path, bool require_xyz) {
  const Parser p(path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) p.fail("file does not exist");
  if (std::filesystem::file_size(path, ec) == 0 || ec) p.fail("file is empty");
  std::ifstream in(path, std::ios::binary);
  PcdHeader h;
  HeaderReader reader(p, h);
  bool done = false;
  std::string line;
  for (std::size_t n = 0; n < kMaxHeaderLines && !done; ++n) {
    if (!std::getline(in, line)) p.fail("header ends before its DATA line");
    if (line.empty() || line[0] == '#') continue;
    const auto w = words(line);
    if (w.empty()) continue;
    done = reader.take(w);
  }
  if (!done) p.fail("header has no DATA line in its first 64 lines");
  h.data_offset = std::uint64_t(in.tellg());
  checkPoints(p, h, require_xyz);
  return h;
}

PcdCloud readPcd(const std::filesystem::path& path, bool require_xyz) {
  const Parser p(path);
  PcdCloud c;
  c.header = readPcdHeader(path, require_xyz);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in.tellg();
  std::string rest(
      std::size_t(std::max<std::streamoff>(0, size - std::streamoff(c.header.data_offset))), '\0');
  in.seekg(std::streamoff(c.header.data_offset));
  in.read(rest.data(), std::streamsize(rest.size()));
  if (in.gcount() != std::streamsize(rest.size())) p.fail("cannot be read past its header");
  if (c.header.data == "ascii")
    readAscii(p, c, rest);
  else if (c.header.data == "binary")
    readBinary(p, c, rest);
  else
    readCompressed(p, c, rest);
  return c;
}

}  // namespace ambler::io
