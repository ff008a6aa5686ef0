#include "io/ReplaceFile.h"

#include <system_error>

#include "io/FormatError.h"

namespace ambler::io {

void writeThenReplace(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path& partial)>& write) {
  auto partial = path;
  partial += ".partial";
  std::error_code ec;
  try {
    write(partial);
  } catch (...) {
    std::filesystem::remove(partial, ec);
    throw;
  }
  std::filesystem::rename(partial, path, ec);
  if (!ec) return;
  std::error_code ignored;
  std::filesystem::remove(partial, ignored);
  throw FormatError("'" + path.string() + "': cannot move the finished file into place (" +
                    ec.message() + ")");
}

}  // namespace ambler::io
