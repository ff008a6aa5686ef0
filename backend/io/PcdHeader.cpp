#include "io/PcdHeader.h"

#include <algorithm>
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
constexpr std::size_t kMaxHeaderLines = 64;

class HeaderParser {
 public:
  explicit HeaderParser(const std::filesystem::path& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw FormatError("PCD '" + path_.string() + "': " + problem);
  }

  std::uint64_t number(std::istringstream& in, const std::string& key, std::uint64_t max) const {
    std::string token;
    if (!(in >> token) || token.find_first_not_of("0123456789") != std::string::npos ||
        token.size() > 12)
      fail(key + " must be a whole number");
    const std::uint64_t value = std::stoull(token);
    if (value > max) fail(key + " " + token + " is more than " + std::to_string(max));
    return value;
  }

  template <typename T, typename Convert>
  std::vector<T> list(std::istringstream& in, const std::string& key, Convert convert) const {
    std::vector<T> out;
    std::string token;
    while (in >> token) {
      if (out.size() == kMaxFields) fail(key + " lists more than 256 entries");
      out.push_back(convert(token));
    }
    if (out.empty()) fail(key + " is empty");
    return out;
  }

 private:
  const std::filesystem::path& path_;
};

void checkConsistency(const HeaderParser& p, const PcdHeader& h, bool require_xyz) {
  if (h.fields.empty()) p.fail("no FIELDS line");
  if (h.sizes.size() != h.fields.size() || h.types.size() != h.fields.size() ||
      h.counts.size() != h.fields.size())
    p.fail("FIELDS, SIZE, TYPE and COUNT list different numbers of entries (" +
           std::to_string(h.fields.size()) + ", " + std::to_string(h.sizes.size()) + ", " +
           std::to_string(h.types.size()) + ", " + std::to_string(h.counts.size()) + ")");
  for (std::size_t i = 0; i < h.fields.size(); ++i)
    if (h.types[i] == 'F' && h.sizes[i] != 4 && h.sizes[i] != 8)
      p.fail("field " + h.fields[i] + " is a float of " + std::to_string(h.sizes[i]) + " bytes");
  if (require_xyz)
    for (const char* axis : {"x", "y", "z"})
      if (!h.hasField(axis)) p.fail(std::string("no field ") + axis);
  if (h.width == 0 || h.height == 0 || h.points == 0) p.fail("has no points");
  if (h.width * h.height != h.points)
    p.fail("WIDTH x HEIGHT (" + std::to_string(h.width) + " x " + std::to_string(h.height) +
           ") is not POINTS (" + std::to_string(h.points) + ")");
}

void checkLength(const HeaderParser& p, const PcdHeader& h, std::ifstream& in,
                 std::uint64_t file_size) {
  const std::uint64_t left = file_size - h.data_offset;
  const std::uint64_t needed = h.points * h.pointBytes();
  if (h.data == "binary" && left < needed)
    p.fail("truncated: " + std::to_string(h.points) + " points need " + std::to_string(needed) +
           " bytes, the file has " + std::to_string(left) + " after its header");
  if (h.data == "binary_compressed") {
    std::uint32_t sizes[2] = {0, 0};
    if (left < 8 || !in.read(reinterpret_cast<char*>(sizes), 8))
      p.fail("truncated: no compressed block sizes after the header");
    if (sizes[0] > left - 8)
      p.fail("truncated: the compressed block of " + std::to_string(sizes[0]) +
             " bytes is longer than the " + std::to_string(left - 8) + " bytes left");
    if (sizes[1] != needed)
      p.fail("the compressed block unpacks to " + std::to_string(sizes[1]) + " bytes, not the " +
             std::to_string(needed) + " its points need");
  }
}

}  // namespace

std::uint64_t PcdHeader::pointBytes() const {
  std::uint64_t bytes = 0;
  for (std::size_t i = 0; i < sizes.size(); ++i) bytes += std::uint64_t(sizes[i]) * counts[i];
  return bytes;
}

bool PcdHeader::hasField(const std::string& name) const {
  return std::find(fields.begin(), fields.end(), name) != fields.end();
}

PcdHeader checkPcd(const std::filesystem::path& path, bool require_xyz) {
  const HeaderParser p(path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) p.fail("file does not exist");
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec || file_size == 0) p.fail("the file is empty");
  std::ifstream in(path, std::ios::binary);
  PcdHeader h;
  bool points_given = false;
  std::string line;
  for (std::size_t n = 0; n < kMaxHeaderLines && h.data.empty(); ++n) {
    if (!std::getline(in, line)) p.fail("the header ends before its DATA line");
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "FIELDS") {
      h.fields = p.list<std::string>(words, key, [](const std::string& t) { return t; });
    } else if (key == "SIZE") {
      h.sizes = p.list<int>(words, key, [&](const std::string& t) {
        if (t != "1" && t != "2" && t != "4" && t != "8")
          p.fail("SIZE " + t + " is not 1, 2, 4 or 8");
        return std::stoi(t);
      });
    } else if (key == "TYPE") {
      h.types = p.list<char>(words, key, [&](const std::string& t) {
        if (t != "I" && t != "U" && t != "F") p.fail("TYPE " + t + " is not I, U or F");
        return t[0];
      });
    } else if (key == "COUNT") {
      h.counts = p.list<int>(words, key, [&](const std::string& t) {
        std::istringstream one(t);
        return int(p.number(one, "COUNT", 65536));
      });
      if (std::count(h.counts.begin(), h.counts.end(), 0)) p.fail("a COUNT is 0");
    } else if (key == "WIDTH") {
      h.width = p.number(words, key, kMaxPoints);
    } else if (key == "HEIGHT") {
      h.height = p.number(words, key, kMaxPoints);
    } else if (key == "POINTS") {
      h.points = p.number(words, key, kMaxPoints), points_given = true;
    } else if (key == "DATA") {
      words >> h.data;
      if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
        p.fail("DATA '" + h.data + "' is not ascii, binary or binary_compressed");
    } else if (key != "VERSION" && key != "VIEWPOINT") {
      p.fail("unknown header line '" + line.substr(0, 40) + "'");
    }
  }
  if (h.data.empty()) p.fail("no DATA line in the first 64 lines");
  if (h.counts.empty()) h.counts.assign(h.fields.size(), 1);
  if (!points_given) h.points = h.width * h.height;
  h.data_offset = std::uint64_t(in.tellg());
  checkConsistency(p, h, require_xyz);
  checkLength(p, h, in, file_size);
  return h;
}

}  // namespace ambler::io
