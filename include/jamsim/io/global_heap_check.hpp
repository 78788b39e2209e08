#pragma once
// HDF5 keeps variable-length data (jamsim's text attributes) in global heap collections, and
// HDF5 1.10 loops for ever parsing a collection whose objects a crash zeroed (an object of size
// 0 never advances its parser). A small file, such as a checkpoint, is checked here first, so
// that such damage is a damaged file (its replica starts again), not a hung run.

#include <string>

namespace jamsim {

/// "" when every global heap collection in the file at `path` parses to its end as HDF5's
/// parser walks it; else where it does not ("the global heap at byte 2048 holds an object of
/// size 0"). Reads the whole file: for files of a few MB, not for archives. A file that cannot
/// be read gives "" (the reader that follows says why).
std::string damaged_global_heap(const std::string& path);

}  // namespace jamsim
