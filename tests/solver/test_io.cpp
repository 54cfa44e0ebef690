// HDF5 writer: datasets in nested groups, tables, attributes, round trip through the reader, and
// the write-then-rename contract (no file at the final path until close()).
#include "io/hdf5.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

using namespace sph::io;
namespace fs = std::filesystem;

TEST(Hdf5, RoundTripAndAtomicRename) {
  const fs::path dir = fs::temp_directory_path() / ("sph_io_" + std::to_string(getpid()));
  fs::remove_all(dir);
  const fs::path file = dir / "out.h5";
  {
    H5Writer w(file);
    w.write("series/t", {0.0, 0.5, 1.0});
    w.write_columns("forces", {"cd", "cl"}, {{1.3, 1.4}, {0.1, -0.1}});
    w.write("field/u", {1, 2, 3, 4, 5, 6}, {2, 3});
    w.attribute("case", "cylinder_channel");
    w.attribute("Re", 100.0);
    EXPECT_FALSE(fs::exists(file)); // still under its temporary name
    w.close();
    EXPECT_TRUE(fs::exists(file));
  }
  EXPECT_EQ(read_dataset(file, "series/t"), (std::vector<double>{0.0, 0.5, 1.0}));
  EXPECT_EQ(read_dataset(file, "forces/cl"), (std::vector<double>{0.1, -0.1}));
  EXPECT_EQ(read_dataset(file, "field/u").size(), 6u);
  EXPECT_THROW(read_dataset(file, "missing"), std::runtime_error);
  H5Writer bad(dir / "bad.h5");
  EXPECT_THROW(bad.write("x", {1, 2, 3}, {2, 2}), std::runtime_error);
  EXPECT_THROW(bad.write_columns("g", {"a", "b"}, {{1}, {1, 2}}), std::runtime_error);
  bad.close();
  fs::remove_all(dir);
}
