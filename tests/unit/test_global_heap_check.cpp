// The check of a small HDF5 file's global heap collections (where its variable-length text
// attributes live) against the damage HDF5 1.10 loops on: objects zeroed by a crash.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "jamsim/io/global_heap_check.hpp"
#include "jamsim/io/hdf5.hpp"

namespace {

std::string write_file_with_text(const std::string& name) {
    const std::string path = (std::filesystem::temp_directory_path() / name).string();
    jamsim::h5::FileInMemory file(path);
    jamsim::h5::write_attribute(file.get(), "format", std::string("a text attribute in the global heap"));
    file.write_and_close();
    return path;
}

/// Zeroes the objects of the first collection ("GCOL", version, reserved, size, objects).
void zero_first_heap(const std::string& path) {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const std::size_t at = data.find("GCOL");
    ASSERT_NE(at, std::string::npos);
    std::uint64_t size = 0;
    for (int k = 0; k < 8; ++k)
        size |= static_cast<std::uint64_t>(static_cast<unsigned char>(data[at + 8 + k])) << (8 * k);
    f.clear();
    f.seekp(static_cast<std::streamoff>(at + 16));
    const std::string zeros(size - 16, '\0');
    f.write(zeros.data(), static_cast<std::streamsize>(zeros.size()));
}

}  // namespace

TEST(GlobalHeapCheck, IntactFileIsIntactAndZeroedObjectsAreFound) {
    const std::string path = write_file_with_text("jamsim_heap_check.h5");
    EXPECT_EQ(jamsim::damaged_global_heap(path), "");
    zero_first_heap(path);
    const std::string why = jamsim::damaged_global_heap(path);
    EXPECT_NE(why.find("holds an object of size 0"), std::string::npos) << why;
    std::filesystem::remove(path);
}

TEST(GlobalHeapCheck, UnreadableFileIsLeftToItsReader) {
    EXPECT_EQ(jamsim::damaged_global_heap("/no/such/file.h5"), "");
}
