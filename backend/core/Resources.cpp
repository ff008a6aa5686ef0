#include "core/Resources.h"

#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace ambler {

namespace {

std::filesystem::path executableDir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path{} : exe.parent_path();
}

}  // namespace

std::filesystem::path findResource(const std::string& relative_path) {
  std::vector<std::filesystem::path> roots;
  if (const char* env = std::getenv("AMBLER_DATA_DIR"); env && *env) roots.emplace_back(env);
  if (const auto exe_dir = executableDir(); !exe_dir.empty())
    roots.push_back(exe_dir / ".." / "share" / "ambler");
  roots.emplace_back(AMBLER_SOURCE_DATA_DIR);

  std::string tried;
  for (const auto& root : roots) {
    const auto candidate = root / relative_path;
    if (std::filesystem::is_regular_file(candidate)) return candidate.lexically_normal();
    tried += "\n  " + candidate.lexically_normal().string();
  }
  throw std::runtime_error("resource '" + relative_path + "' not found; looked in:" + tried);
}

}  // namespace ambler
