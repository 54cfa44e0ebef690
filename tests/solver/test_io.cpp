// HDF5 writer: datasets in nested groups, tables, typed attributes, round trip through the reader,
// and the write-then-rename contract (no file at the final path until close()).
#include "io/hdf5.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

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

// Typed root attributes (issue 16 part 2): an integer stays an integer, a string a (variable-length
// UTF-8) string, a boolean h5py's bool enum, and writing a key again replaces its attribute.
TEST(Hdf5, TypedAttributes) {
  const fs::path dir = fs::temp_directory_path() / ("sph_io_attr_" + std::to_string(getpid()));
  fs::remove_all(dir);
  const fs::path file = dir / "attr.h5";
  {
    H5Writer w(file);
    w.attribute("n_side", 50);
    w.attribute("seed", std::int64_t{1} << 40);
    w.attribute("Re", 100.0);
    w.attribute("tvf", std::string("limited"));
    w.attribute("case", "taylor_green");
    w.attribute_bool("kernel_correction", true);
    w.attribute("Re", 200.0); // replaced
    w.close();
  }
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  auto cls = [&](const char* key) {
    const hid_t a = H5Aopen(f, key, H5P_DEFAULT);
    const hid_t t = H5Aget_type(a);
    const H5T_class_t c = H5Tget_class(t);
    H5Tclose(t), H5Aclose(a);
    return c;
  };
  EXPECT_EQ(cls("n_side"), H5T_INTEGER);
  EXPECT_EQ(cls("seed"), H5T_INTEGER);
  EXPECT_EQ(cls("Re"), H5T_FLOAT);
  EXPECT_EQ(cls("tvf"), H5T_STRING);
  EXPECT_EQ(cls("kernel_correction"), H5T_ENUM);
  std::int64_t seed = 0, n_side = 0;
  double re = 0.0;
  const hid_t a1 = H5Aopen(f, "seed", H5P_DEFAULT), a2 = H5Aopen(f, "n_side", H5P_DEFAULT),
              a3 = H5Aopen(f, "Re", H5P_DEFAULT), a4 = H5Aopen(f, "case", H5P_DEFAULT);
  H5Aread(a1, H5T_NATIVE_INT64, &seed);
  H5Aread(a2, H5T_NATIVE_INT64, &n_side);
  H5Aread(a3, H5T_NATIVE_DOUBLE, &re);
  const hid_t st = H5Aget_type(a4);
  EXPECT_GT(H5Tis_variable_str(st), 0);
  char* text = nullptr;
  H5Aread(a4, st, &text);
  EXPECT_STREQ(text, "taylor_green");
  H5free_memory(text);
  H5Tclose(st);
  for (hid_t a : {a1, a2, a3, a4})
    H5Aclose(a);
  H5Fclose(f);
  EXPECT_EQ(seed, std::int64_t{1} << 40);
  EXPECT_EQ(n_side, 50);
  EXPECT_EQ(re, 200.0);
  fs::remove_all(dir);
}
