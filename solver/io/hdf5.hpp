// HDF5 output of a job: time series, fields and attributes in one file (the job's
// <output_dir>/<name>.h5). Thin RAII wrapper over the HDF5 C API (serial library, Debian's
// libhdf5-dev). Dataset paths may contain groups ("series/cd"); groups are created as needed.
// Files are written to "<path>.tmp" and renamed into place by close() (or the destructor), so a
// reader never sees a half-written file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sph::io {

class H5Writer {
public:
  explicit H5Writer(std::filesystem::path path); // throws std::runtime_error
  ~H5Writer();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  // A dataset of doubles; dims empty means one-dimensional of data.size().
  void write(const std::string& name, const std::vector<double>& data,
             std::vector<std::uint64_t> dims = {});
  // A table: one 1-D dataset per column under `group`, all of the same length.
  void write_columns(const std::string& group, const std::vector<std::string>& names,
                     const std::vector<std::vector<double>>& columns);
  // Attributes on the file's root group, typed: a string (variable-length UTF-8), a double
  // (IEEE 64-bit), an integer (signed 64-bit) or a boolean (the HDF5 enum h5py writes for numpy
  // bool: FALSE = 0, TRUE = 1 over an 8-bit integer; h5py reads it back as a bool). Writing a
  // key again replaces its attribute.
  void attribute(const std::string& key, const std::string& value);
  void attribute(const std::string& key, double value);
  void attribute(const std::string& key, std::int64_t value);
  void attribute(const std::string& key, int value) {
    attribute(key, static_cast<std::int64_t>(value));
  }
  void attribute_bool(const std::string& key, bool value);

  // Flushes, closes and renames the file into place. Idempotent.
  void close();

private:
  std::filesystem::path path_, tmp_;
  std::int64_t file_ = -1; // hid_t
  void ensure_groups(const std::string& name);
  void scalar_attribute(const std::string& key, std::int64_t type, const void* value);
};

// Reads a whole 1-D (or flattened N-D) dataset of doubles.
std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& name);

// A string attribute of the file's root group (as H5Writer::attribute writes it); nullopt when
// the file has no attribute of that name. Throws when the file or the attribute cannot be read.
std::optional<std::string> read_string_attribute(const std::filesystem::path& file,
                                                 const std::string& key);

} // namespace sph::io
