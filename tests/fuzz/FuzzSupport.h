#pragma once

// What the fuzz targets share: a scratch file for readers that take a path,
// and seeding an empty corpus with valid inputs at start-up, so that no
// generated data is committed and each run starts from real files.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace ambler::fuzz {

using Bytes = std::vector<std::uint8_t>;

// A directory of this process's own, removed at exit. Its name has the same
// length whatever the pid, so paths cannot steer a target's coverage.
inline std::filesystem::path scratchPath() {
  char name[32];
  std::snprintf(name, sizeof name, "ambler-fuzz-%010d", int(::getpid()));
  return std::filesystem::temp_directory_path() / name;
}

inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::create_directories(scratchPath());
    // Not `dir` itself: statics are destroyed before this runs.
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratchPath(), ec);
    });
    return scratchPath();
  }();
  return dir;
}

inline std::filesystem::path writeScratch(const std::string& name, const std::uint8_t* data,
                                          std::size_t size) {
  const auto path = scratchDir() / name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

inline Bytes readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

// libFuzzer's positional arguments are corpus directories; the first one,
// if empty, gets `seeds()`.
inline void seedCorpus(int argc, char** argv, const std::function<std::vector<Bytes>()>& seeds) {
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] == '-') continue;
    const std::filesystem::path dir(argv[i]);
    if (!std::filesystem::is_directory(dir) || !std::filesystem::is_empty(dir)) return;
    int n = 0;
    for (const auto& s : seeds())
      std::ofstream(dir / ("seed-" + std::to_string(n++)), std::ios::binary)
          .write(reinterpret_cast<const char*>(s.data()), std::streamsize(s.size()));
    return;
  }
}

// An exception other than the reader's documented one is a defect: the
// caller would not turn it into a clear message.
[[noreturn]] inline void unexpected(const char* what) {
  std::fprintf(stderr, "unexpected exception: %s\n", what);
  std::abort();
}

// Runs `read`: its documented refusal `Refusal` is an answer, any other
// exception a defect.
template <typename Refusal, typename Read>
void refusalOnly(Read read) {
  try {
    read();
  } catch (const Refusal&) {
  } catch (const std::exception& e) {
    unexpected(e.what());
  }
}

}  // namespace ambler::fuzz
