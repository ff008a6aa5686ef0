#pragma once

#include <filesystem>
#include <functional>

namespace ambler::io {

// Writes a file that no reader ever finds half written: `write` fills
// `path` + ".partial", which then takes the place of `path` in one rename.
// When `write` throws or the rename fails, the partial file is removed and
// `path` is left as it was; a failed rename throws FormatError naming
// `path`, and what `write` throws passes through.
void writeThenReplace(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path& partial)>& write);

}  // namespace ambler::io
