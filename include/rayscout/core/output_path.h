// Checking an output path before the work that ends by writing it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace rayscout {

/// Throws InputError, prefixed with `label` (e.g. "--stats out.json"), unless `path` can be
/// written as a file: it is not a directory, its folder exists, and it opens for writing (an
/// existing file is left as it is, a new one is removed again). Commands call it before long
/// work, so that a mistyped or unwritable output path never costs a finished render.
void check_output_path(const std::filesystem::path& path, const std::string& label);

/// Writes bytes to path, replacing it, and checks the write only after closing the file: a full
/// disk is often reported only by the last flush. Throws InputError "label: cannot write
/// path (...)" on any failure.
void write_file(const std::filesystem::path& path, std::string_view bytes, const std::string& label);

}  // namespace rayscout
