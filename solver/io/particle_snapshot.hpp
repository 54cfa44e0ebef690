// Particle snapshots ParaView opens directly: one VTK XML PolyData file (.vtp) per output time,
// every particle a vertex, and a ParaView collection file (.pvd) listing them with their times,
// which ParaView loads as one animated data set (issue 16, part 1; docs/fields.md).
//
// Formats: "VTK File Formats" (VTK User's Guide, 11th ed., Kitware 2010, and
// https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html): XML PolyData with one
// Verts cell per point, little-endian, header_type UInt64, the arrays in one raw appended block;
// the .pvd "Collection" of ParaView (one DataSet element per time step, timestep and file
// attributes). Chosen by testing ParaView 5.11 (Debian 12) with pvpython: the .pvd of .vtp files
// opens as one time series with every array; see docs/fields.md for what else was tried.
//
// A snapshot holds, for every particle of every kind: Points (x, y, z; z = 0 in 2D), velocity
// (3 components), pressure, density, mass, volume, smoothing_length, kind (0 fluid, 1 wall,
// 2 body, 3 buffer, 4 solid: core/particles.hpp's Kind), id (index at creation), and every extra
// named field the particle set carries (scheme or case fields such as drho_dt or v_wall), plus the
// field-data array TimeValue.
//
// Layout in a job's output directory: particles.pvd and particles/particles_NNNNNN.vtp. Every
// file is written to NAME.tmp and renamed into place, so a reader (ParaView on a running job)
// never sees a half-written one.
#pragma once

#include "core/particles.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace sph::io {

// One per-point array: name, components per point (1 or 3) and its values in one of three types
// (exactly one of f64, i64, u8 holds components * points values).
struct PointArray {
  std::string name;
  int components = 1;
  std::vector<double> f64;
  std::vector<std::int64_t> i64;
  std::vector<std::uint8_t> u8;
};

// A point cloud at one time: positions (3 per point) and its point arrays.
struct PointSet {
  double time = 0.0;
  std::vector<double> points;
  std::vector<PointArray> arrays;
  std::size_t size() const { return points.size() / 3; }
};

// Writes s as VTK XML PolyData (file.tmp, then renamed). Throws std::runtime_error when an
// array's size does not match the points or the file cannot be written.
void write_vtp(const std::filesystem::path& file, const PointSet& s);

// A .pvd entry: time and file name relative to the .pvd's folder.
struct SeriesEntry {
  double time = 0.0;
  std::string file;
};
void write_pvd(const std::filesystem::path& file, const std::vector<SeriesEntry>& entries);
// The entries of a .pvd written by write_pvd (empty when the file does not exist).
std::vector<SeriesEntry> read_pvd(const std::filesystem::path& file);

// The point set of particles p at time t: the fields listed at the top. h_field >= 0: the index
// of p's scalar field holding per-particle smoothing lengths (written as smoothing_length, not
// again under its own name); otherwise every particle has smoothing length h.
template <int D>
PointSet particle_point_set(const Particles<D>& p, double t, double h, int h_field = -1) {
  const std::size_t n = p.size();
  PointSet s;
  s.time = t;
  auto vec3 = [n](const std::vector<Vec<D>>& v) {
    std::vector<double> out(3 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < D; ++a)
        out[3 * i + a] = v[i][a];
    return out;
  };
  s.points = vec3(p.r);
  s.arrays.push_back({"velocity", 3, vec3(p.v), {}, {}});
  s.arrays.push_back({"pressure", 1, p.p, {}, {}});
  s.arrays.push_back({"density", 1, p.rho, {}, {}});
  s.arrays.push_back({"mass", 1, p.m, {}, {}});
  s.arrays.push_back({"volume", 1, p.V, {}, {}});
  s.arrays.push_back({"smoothing_length",
                      1,
                      h_field >= 0 ? p.scalar(h_field) : std::vector<double>(n, h),
                      {},
                      {}});
  PointArray kind{"kind", 1, {}, {}, std::vector<std::uint8_t>(n)};
  for (std::size_t i = 0; i < n; ++i)
    kind.u8[i] = static_cast<std::uint8_t>(p.kind[i]);
  s.arrays.push_back(std::move(kind));
  s.arrays.push_back({"id", 1, {}, p.id, {}});
  for (int k = 0; k < p.scalar_count(); ++k)
    if (k != h_field)
      s.arrays.push_back({p.scalar_name(k), 1, p.scalar(k), {}, {}});
  for (int k = 0; k < p.vector_count(); ++k)
    s.arrays.push_back({p.vector_name(k), 3, vec3(p.vector(k)), {}, {}});
  return s;
}

// The snapshot series of one run in `dir` (particles.pvd and particles/): the state every
// `interval` of simulated time (interval <= 0: none between) and the final state.
//
// A snapshot is due at the end of the first step that reaches t >= k interval (k = 1, 2, ...):
// the loop's time steps are never changed for an output, so snapshot times are step times, not
// exact multiples. A run that starts at step 0 clears the folder and writes the initial state
// (when interval > 0); a run resumed from a checkpoint at time t keeps the snapshots of times
// <= t (written before the checkpoint, as the loop writes snapshots before it saves) and drops
// later ones (written after the checkpoint by the interrupted attempt).
class SnapshotSeries {
public:
  // dir empty: disabled (every call does nothing).
  SnapshotSeries(std::filesystem::path dir, double interval);
  bool enabled() const { return !dir_.empty(); }
  // Start of a run at time t after `steps` steps (steps > 0: resumed from a checkpoint). Returns
  // true when the initial state must be written (a fresh run with interval > 0).
  bool start(double t, long steps);
  // True when the step that ended at time t is due for a snapshot.
  bool due(double t) const;
  // True when the state of step `steps` was not yet written (the final state's test).
  bool written(long steps) const { return last_step_ == steps; }
  // Writes s as the next snapshot (of step `steps`) and rewrites the .pvd.
  void write(const PointSet& s, long steps);
  const std::vector<SeriesEntry>& entries() const { return entries_; }
  std::filesystem::path pvd() const { return dir_ / "particles.pvd"; }

private:
  std::filesystem::path dir_;
  double interval_;
  long next_k_ = 1;     // the next multiple of interval due
  long last_step_ = -1; // the step of the last snapshot written
  std::vector<SeriesEntry> entries_;
  void advance_k(double t);
};

// The time loop's hook (cases/time_loop.hpp): the snapshot series of particles p with the
// scheme's smoothing length h (or p's per-particle field h_field), in output_dir.
template <int D>
class ParticleSnapshots {
public:
  ParticleSnapshots(const std::filesystem::path& output_dir, double interval, const Particles<D>& p,
                    int h_field, double h, double t, long steps)
      : series_(output_dir, interval), p_(p), h_field_(h_field), h_(h) {
    if (series_.start(t, steps))
      series_.write(particle_point_set(p_, t, h_, h_field_), steps);
  }
  // After the step that ended at time t (the `steps`-th): a snapshot when one is due.
  void after_step(double t, long steps) {
    if (series_.enabled() && series_.due(t))
      series_.write(particle_point_set(p_, t, h_, h_field_), steps);
  }
  // The final state (a finished or diverged run), unless this step was just written.
  void final_state(double t, long steps) {
    if (series_.enabled() && !series_.written(steps))
      series_.write(particle_point_set(p_, t, h_, h_field_), steps);
  }

private:
  SnapshotSeries series_;
  const Particles<D>& p_;
  int h_field_;
  double h_;
};

} // namespace sph::io
