// HDF5 writer and reader (see hdf5.hpp).
#include "io/hdf5.hpp"

#include <hdf5.h>

#include <stdexcept>

namespace sph::io {

namespace {
[[noreturn]] void fail(const std::string& what, const std::filesystem::path& p) {
  throw std::runtime_error("HDF5: " + what + " (" + p.string() + ")");
}
} // namespace

H5Writer::H5Writer(std::filesystem::path path) : path_(std::move(path)) {
  tmp_ = path_;
  tmp_ += ".tmp";
  if (path_.has_parent_path())
    std::filesystem::create_directories(path_.parent_path());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // errors are reported by return codes
  file_ = H5Fcreate(tmp_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0)
    fail("cannot create file", tmp_);
}

H5Writer::~H5Writer() {
  try {
    close();
  } catch (...) {
  }
}

void H5Writer::close() {
  if (file_ < 0)
    return;
  H5Fflush(file_, H5F_SCOPE_GLOBAL);
  const herr_t st = H5Fclose(file_);
  file_ = -1;
  if (st < 0)
    fail("cannot close file", tmp_);
  std::filesystem::rename(tmp_, path_);
}

void H5Writer::ensure_groups(const std::string& name) {
  for (std::size_t pos = name.find('/'); pos != std::string::npos; pos = name.find('/', pos + 1)) {
    const std::string g = name.substr(0, pos);
    if (g.empty())
      continue;
    if (H5Lexists(file_, g.c_str(), H5P_DEFAULT) > 0)
      continue;
    const hid_t id = H5Gcreate2(file_, g.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (id < 0)
      fail("cannot create group " + g, path_);
    H5Gclose(id);
  }
}

void H5Writer::write(const std::string& name, const std::vector<double>& data,
                     std::vector<std::uint64_t> dims) {
  if (file_ < 0)
    fail("write after close", path_);
  if (dims.empty())
    dims = {data.size()};
  std::uint64_t total = 1;
  for (auto d : dims)
    total *= d;
  if (total != data.size())
    fail("dataset " + name + ": dims do not match the data size", path_);
  ensure_groups(name);
  std::vector<hsize_t> hd(dims.begin(), dims.end());
  const hid_t space = H5Screate_simple(static_cast<int>(hd.size()), hd.data(), nullptr);
  const hid_t set = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT);
  if (set < 0) {
    H5Sclose(space);
    fail("cannot create dataset " + name, path_);
  }
  const herr_t st = H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Dclose(set);
  H5Sclose(space);
  if (st < 0)
    fail("cannot write dataset " + name, path_);
}

void H5Writer::write_columns(const std::string& group, const std::vector<std::string>& names,
                             const std::vector<std::vector<double>>& columns) {
  if (names.size() != columns.size())
    fail("write_columns: names and columns differ", path_);
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (columns[k].size() != columns[0].size())
      fail("write_columns: ragged columns", path_);
    write(group + "/" + names[k], columns[k]);
  }
}

// A scalar attribute of HDF5 type `type` (file and memory type alike) on the root group; an
// attribute of that name is replaced.
void H5Writer::scalar_attribute(const std::string& key, std::int64_t type, const void* value) {
  if (file_ < 0)
    fail("attribute after close", path_);
  if (H5Aexists(file_, key.c_str()) > 0 && H5Adelete(file_, key.c_str()) < 0)
    fail("cannot replace attribute " + key, path_);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(file_, key.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t st = attr < 0 ? -1 : H5Awrite(attr, type, value);
  if (attr >= 0)
    H5Aclose(attr);
  H5Sclose(space);
  if (st < 0)
    fail("cannot write attribute " + key, path_);
}

void H5Writer::attribute(const std::string& key, const std::string& value) {
  // A variable-length UTF-8 string: what h5py writes for a Python str and reads back as one.
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  const char* text = value.c_str();
  try {
    scalar_attribute(key, type, &text);
  } catch (...) {
    H5Tclose(type);
    throw;
  }
  H5Tclose(type);
}

void H5Writer::attribute(const std::string& key, double value) {
  scalar_attribute(key, H5T_NATIVE_DOUBLE, &value);
}

void H5Writer::attribute(const std::string& key, std::int64_t value) {
  scalar_attribute(key, H5T_NATIVE_INT64, &value);
}

void H5Writer::attribute_bool(const std::string& key, bool value) {
  const hid_t type = H5Tenum_create(H5T_NATIVE_INT8);
  const std::int8_t f = 0, t = 1, v = value ? 1 : 0;
  H5Tenum_insert(type, "FALSE", &f);
  H5Tenum_insert(type, "TRUE", &t);
  try {
    scalar_attribute(key, type, &v);
  } catch (...) {
    H5Tclose(type);
    throw;
  }
  H5Tclose(type);
}

std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& name) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0)
    fail("cannot open file", file);
  const hid_t set = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  if (set < 0) {
    H5Fclose(f);
    fail("no dataset " + name, file);
  }
  const hid_t space = H5Dget_space(set);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<double> out(static_cast<std::size_t>(n));
  const herr_t st = H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(space);
  H5Dclose(set);
  H5Fclose(f);
  if (st < 0)
    fail("cannot read dataset " + name, file);
  return out;
}

std::optional<std::string> read_string_attribute(const std::filesystem::path& file,
                                                 const std::string& key) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0)
    fail("cannot open file", file);
  const htri_t exists = H5Aexists(f, key.c_str());
  if (exists == 0) {
    H5Fclose(f);
    return std::nullopt;
  }
  const hid_t attr = exists > 0 ? H5Aopen(f, key.c_str(), H5P_DEFAULT) : -1;
  const hid_t ftype = attr >= 0 ? H5Aget_type(attr) : -1;
  std::optional<std::string> out;
  if (ftype >= 0 && H5Tget_class(ftype) == H5T_STRING && H5Tis_variable_str(ftype) > 0) {
    const hid_t mtype = H5Tcopy(H5T_C_S1);
    H5Tset_size(mtype, H5T_VARIABLE);
    H5Tset_cset(mtype, H5Tget_cset(ftype));
    char* text = nullptr;
    if (H5Aread(attr, mtype, &text) >= 0 && text) {
      out = std::string(text);
      H5free_memory(text);
    }
    H5Tclose(mtype);
  }
  if (ftype >= 0)
    H5Tclose(ftype);
  if (attr >= 0)
    H5Aclose(attr);
  H5Fclose(f);
  if (!out)
    fail("cannot read string attribute " + key, file);
  return out;
}

} // namespace sph::io
