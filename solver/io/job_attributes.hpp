// The root attributes that tie a job's HDF5 output to its job (issue 16, part 2): job_key (the
// runner's SHA-256 job key, when the run has one: RunContext::job_key), case, and every resolved
// parameter of the job under its own name with its own type: Int as a 64-bit integer, Real as a
// double, String as a string, Bool as h5py's boolean enum (io/hdf5.hpp). A reader (h5py:
// f.attrs["n_side"] is an integer, f.attrs["tvf"] a string) needs no table of the case's
// parameters to know what made the file.
//
// open_job_output: a case's HDF5 output, <output_dir>/<case>.h5 with these attributes written, or
// nullptr when the job has no output directory (a unit test, `runner one` without one).
#pragma once

#include "core/params.hpp"
#include "core/run.hpp"
#include "io/hdf5.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <variant>

namespace sph::io {

inline void write_job_attributes(H5Writer& w, const std::string& case_name, const Params& prm,
                                 const std::string& job_key) {
  if (!job_key.empty())
    w.attribute("job_key", job_key);
  w.attribute("case", case_name);
  for (const auto& [k, v] : prm) {
    if (const auto* b = std::get_if<bool>(&v))
      w.attribute_bool(k, *b);
    else if (const auto* i = std::get_if<std::int64_t>(&v))
      w.attribute(k, *i);
    else if (const auto* x = std::get_if<double>(&v))
      w.attribute(k, *x);
    else
      w.attribute(k, std::get<std::string>(v));
  }
}

inline std::unique_ptr<H5Writer> open_job_output(const RunContext& ctx,
                                                 const std::string& case_name, const Params& prm) {
  if (ctx.output_dir.empty())
    return nullptr;
  std::filesystem::create_directories(ctx.output_dir);
  auto w = std::make_unique<H5Writer>(ctx.output_dir / (case_name + ".h5"));
  write_job_attributes(*w, case_name, prm, ctx.job_key);
  return w;
}

} // namespace sph::io
