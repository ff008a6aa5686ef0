#include "io/Npz.h"

#include <minizip/unzip.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <regex>

namespace ambler::io {

namespace {

template <typename T>
double valueAt(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // little-endian hosts only (checked by descr)
  return double(v);
}

// The .npy format 1.0-3.0: magic, version, header length, a Python dict
// literal with 'descr', 'fortran_order' and 'shape', then the data.
NpyArray parseNpy(const std::vector<unsigned char>& bytes, const std::string& where) {
  auto fail = [&](const std::string& why) { throw FormatError(where + ": " + why); };
  if (bytes.size() < 10 || std::memcmp(bytes.data(), "\x93NUMPY", 6) != 0)
    fail("not a NumPy array (no \\x93NUMPY magic)");
  const int major = bytes[6];
  const std::size_t length_bytes = major == 1 ? 2 : 4;
  if (major < 1 || major > 3) fail("unsupported .npy version " + std::to_string(major));
  std::size_t header_length = 0;
  for (std::size_t i = 0; i < length_bytes; ++i)
    header_length |= std::size_t(bytes[8 + i]) << (8 * i);
  const std::size_t data_start = 8 + length_bytes + header_length;
  if (data_start > bytes.size()) fail("truncated header");
  const std::string header(bytes.begin() + std::ptrdiff_t(8 + length_bytes),
                           bytes.begin() + std::ptrdiff_t(data_start));
  std::smatch m;
  if (!std::regex_search(header, m, std::regex(R"('descr'\s*:\s*'([<|>])([iuf])(\d)')")))
    fail("unsupported element type in header " + header);
  const char order = m[1].str()[0], kind = m[2].str()[0];
  const int size = std::stoi(m[3].str());
  if (order == '>' && size > 1) fail("big-endian data is not supported");
  if (std::regex_search(header, std::regex(R"('fortran_order'\s*:\s*True)")))
    fail("Fortran-order arrays are not supported");
  if (!std::regex_search(header, m, std::regex(R"('shape'\s*:\s*\(([^)]*)\))")))
    fail("no shape in header " + header);
  NpyArray array;
  std::size_t count = 1;
  const std::string dims = m[1].str();
  const std::regex number(R"(\d+)");
  for (std::sregex_iterator it(dims.begin(), dims.end(), number), end; it != end; ++it) {
    array.shape.push_back(std::stoull(it->str()));
    count *= array.shape.back();
  }
  if (bytes.size() - data_start < count * std::size_t(size))
    fail("truncated data: " + std::to_string(count) + " values of " + std::to_string(size) +
         " bytes announced, " + std::to_string(bytes.size() - data_start) + " bytes present");
  using Reader = double (*)(const unsigned char*);
  Reader read = nullptr;
  if (kind == 'f' && size == 4) read = valueAt<float>;
  if (kind == 'f' && size == 8) read = valueAt<double>;
  if (kind == 'i' && size == 1) read = valueAt<std::int8_t>;
  if (kind == 'i' && size == 2) read = valueAt<std::int16_t>;
  if (kind == 'i' && size == 4) read = valueAt<std::int32_t>;
  if (kind == 'i' && size == 8) read = valueAt<std::int64_t>;
  if (kind == 'u' && size == 1) read = valueAt<std::uint8_t>;
  if (kind == 'u' && size == 2) read = valueAt<std::uint16_t>;
  if (kind == 'u' && size == 4) read = valueAt<std::uint32_t>;
  if (kind == 'u' && size == 8) read = valueAt<std::uint64_t>;
  if (!read) fail("unsupported element type " + std::string(1, kind) + std::to_string(size));
  array.values.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
    array.values.push_back(read(&bytes[data_start + i * std::size_t(size)]));
  return array;
}

}  // namespace

std::map<std::string, NpyArray> readNpz(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::unique_ptr<void, int (*)(unzFile)> zip(unzOpen64(name.c_str()), unzClose);
  if (!zip)
    throw FormatError(
        name + ": " +
        (std::filesystem::exists(path) ? "not a zip archive (.npz)" : "no such file"));
  std::map<std::string, NpyArray> arrays;
  for (int status = unzGoToFirstFile(zip.get()); status == UNZ_OK;
       status = unzGoToNextFile(zip.get())) {
    unz_file_info64 info;
    char entry[512];
    if (unzGetCurrentFileInfo64(zip.get(), &info, entry, sizeof entry, nullptr, 0, nullptr, 0) !=
        UNZ_OK)
      throw FormatError(name + ": unreadable zip directory");
    const std::string where = name + ", entry " + entry;
    if (info.uncompressed_size > (std::uint64_t(1) << 32))
      throw FormatError(where + ": larger than 4 GiB");
    std::vector<unsigned char> bytes(info.uncompressed_size);
    if (unzOpenCurrentFile(zip.get()) != UNZ_OK) throw FormatError(where + ": cannot be opened");
    const int read = unzReadCurrentFile(zip.get(), bytes.data(), unsigned(bytes.size()));
    const int closed = unzCloseCurrentFile(zip.get());
    if (read != int(bytes.size()) || closed != UNZ_OK)
      throw FormatError(where + ": truncated or corrupt (CRC)");
    std::string key = entry;
    if (key.size() > 4 && key.substr(key.size() - 4) == ".npy") key.resize(key.size() - 4);
    arrays[key] = parseNpy(bytes, where);
  }
  if (arrays.empty()) throw FormatError(name + ": holds no arrays");
  return arrays;
}

}  // namespace ambler::io
