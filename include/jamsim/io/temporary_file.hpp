#pragma once
// Outputs are written beside their place and renamed into it, so that a kill or a full disk
// never leaves a partial file under the output's name.

#include <string>

namespace jamsim {

/// A new, empty file beside `path` with a name no other file has (PATH.XXXXXX.tmp, made with
/// O_EXCL), to write the output into before renaming it to `path`: a file the user keeps
/// under PATH.tmp is never overwritten. Throws std::runtime_error naming `path` when it
/// cannot be made.
std::string make_temporary_beside(const std::string& path);

}  // namespace jamsim
