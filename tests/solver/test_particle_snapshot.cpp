// Particle snapshots for ParaView (io/particle_snapshot.hpp, issue 16 part 1): the .vtp files read
// back to the bit (an independent reader of the VTK XML appended-raw layout below), every kind
// and field present in 2D and 3D, the .pvd series' times (an output interval, the final state
// once, a resumed run keeping exactly the snapshots before its checkpoint), and the time loop's
// hook on real cases: the snapshot count and particle count follow from the case's parameters,
// and writing snapshots changes no metric. Also the typed HDF5 root attributes with the job key
// (io/job_attributes.hpp, issue 16 part 2).
#include "cases/case.hpp"
#include "cases/loop_params.hpp"
#include "io/particle_snapshot.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <unistd.h>

using namespace sph;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("sph_snap_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  return d;
}

// A .vtp read back by a reader that knows only the VTK XML format: every appended DataArray as
// doubles (whatever its type), by name, with its type and components; the piece's counts.
struct Vtp {
  std::size_t points = 0, verts = 0;
  double time = std::nan("");
  std::map<std::string, std::vector<double>> arrays;
  std::map<std::string, std::string> types;
  std::map<std::string, int> comps;
};

Vtp read_vtp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Vtp v;
  std::smatch m;
  EXPECT_TRUE(
      std::regex_search(s, m, std::regex("NumberOfPoints=\"(\\d+)\" NumberOfVerts=\"(\\d+)\"")));
  v.points = std::stoul(m[1]), v.verts = std::stoul(m[2]);
  EXPECT_TRUE(std::regex_search(s, m, std::regex("Name=\"TimeValue\"[^>]*>([^<]*)<")));
  v.time = std::stod(m[1]);
  const std::string marker = "<AppendedData encoding=\"raw\">";
  const std::size_t at = s.find(marker);
  EXPECT_NE(at, std::string::npos);
  const std::size_t base = s.find('_', at + marker.size()) + 1;
  static const std::regex arr(
      "<DataArray type=\"(\\w+)\" Name=\"([^\"]+)\" NumberOfComponents=\"(\\d+)\" "
      "format=\"appended\" offset=\"(\\d+)\"/>");
  const std::string head = s.substr(0, at);
  for (auto it = std::sregex_iterator(head.begin(), head.end(), arr); it != std::sregex_iterator();
       ++it) {
    const std::string type = (*it)[1], name = (*it)[2];
    const std::size_t off = base + std::stoul((*it)[4]);
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, s.data() + off, 8);
    const char* d = s.data() + off + 8;
    std::vector<double> out;
    if (type == "Float64")
      for (std::size_t k = 0; k < bytes / 8; ++k) {
        double x;
        std::memcpy(&x, d + 8 * k, 8);
        out.push_back(x);
      }
    else if (type == "Int64")
      for (std::size_t k = 0; k < bytes / 8; ++k) {
        std::int64_t x;
        std::memcpy(&x, d + 8 * k, 8);
        out.push_back(static_cast<double>(x));
      }
    else if (type == "UInt8")
      for (std::size_t k = 0; k < bytes; ++k)
        out.push_back(static_cast<unsigned char>(d[k]));
    else
      ADD_FAILURE() << "unexpected type " << type;
    v.arrays[name] = out, v.types[name] = type, v.comps[name] = std::stoi((*it)[3]);
  }
  return v;
}

// A small particle set of every kind with distinct values in every field and one extra field of
// each sort.
template <int D>
Particles<D> sample_particles() {
  Particles<D> p;
  const int e = p.add_scalar("extra_scalar");
  const int w = p.add_vector("extra_vector");
  const Kind kinds[] = {Kind::Fluid, Kind::Wall, Kind::Body, Kind::Buffer};
  for (int i = 0; i < 11; ++i) {
    Vec<D> x;
    for (int a = 0; a < D; ++a)
      x[a] = 0.1 * i + 0.01 * a + 1.0 / 3.0;
    const std::size_t k = p.add(x, 1e-4 * (i + 1), 1000.0 + i, kinds[i % 4]);
    for (int a = 0; a < D; ++a)
      p.v[k][a] = -0.5 * i + a;
    p.p[k] = 3.0 * i - 7.0, p.V[k] = 2e-7 * i;
    p.scalar(e)[k] = std::sqrt(2.0) * i;
    p.vector(w)[k] = Vec<D>::Constant(-1.0 * i);
  }
  return p;
}

template <int D>
void expect_round_trip() {
  const fs::path dir = fresh_dir("rt" + std::to_string(D));
  const Particles<D> p = sample_particles<D>();
  io::write_vtp(dir / "a.vtp", io::particle_point_set(p, 0.125, 0.013));
  EXPECT_FALSE(fs::exists(dir / "a.vtp.tmp"));
  const Vtp v = read_vtp(dir / "a.vtp");
  const std::size_t n = p.size();
  EXPECT_EQ(v.points, n);
  EXPECT_EQ(v.verts, n);
  EXPECT_EQ(v.time, 0.125);
  for (const char* name :
       {"Points", "velocity", "pressure", "density", "mass", "volume", "smoothing_length", "kind",
        "id", "extra_scalar", "extra_vector", "connectivity", "offsets"})
    EXPECT_TRUE(v.arrays.count(name)) << name;
  EXPECT_EQ(v.types.at("kind"), "UInt8");
  EXPECT_EQ(v.types.at("id"), "Int64");
  EXPECT_EQ(v.comps.at("velocity"), 3);
  EXPECT_EQ(v.comps.at("extra_vector"), 3);
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(v.arrays.at("Points")[3 * i + a], a < D ? p.r[i][a] : 0.0);
      EXPECT_EQ(v.arrays.at("velocity")[3 * i + a], a < D ? p.v[i][a] : 0.0);
      EXPECT_EQ(v.arrays.at("extra_vector")[3 * i + a], a < D ? -1.0 * i : 0.0);
    }
    EXPECT_EQ(v.arrays.at("pressure")[i], p.p[i]);
    EXPECT_EQ(v.arrays.at("density")[i], p.rho[i]);
    EXPECT_EQ(v.arrays.at("mass")[i], p.m[i]);
    EXPECT_EQ(v.arrays.at("volume")[i], p.V[i]);
    EXPECT_EQ(v.arrays.at("smoothing_length")[i], 0.013);
    EXPECT_EQ(v.arrays.at("kind")[i], static_cast<double>(p.kind[i]));
    EXPECT_EQ(v.arrays.at("id")[i], static_cast<double>(p.id[i]));
    EXPECT_EQ(v.arrays.at("extra_scalar")[i], p.scalar(0)[i]);
    EXPECT_EQ(v.arrays.at("connectivity")[i], static_cast<double>(i));
    EXPECT_EQ(v.arrays.at("offsets")[i], static_cast<double>(i + 1));
  }
  // Every kind is present (the writer selects none).
  std::map<double, int> kinds;
  for (double k : v.arrays.at("kind"))
    ++kinds[k];
  EXPECT_EQ(kinds.size(), 4u);
  fs::remove_all(dir);
}

} // namespace

TEST(ParticleSnapshot, VtpRoundTrip2D) {
  expect_round_trip<2>();
}
TEST(ParticleSnapshot, VtpRoundTrip3D) {
  expect_round_trip<3>();
}

// A per-particle smoothing length (variable resolution) is written as smoothing_length and not
// again under the field's own name.
TEST(ParticleSnapshot, PerParticleSmoothingLength) {
  const fs::path dir = fresh_dir("h");
  Particles<2> p = sample_particles<2>();
  const int h = p.add_scalar("h");
  for (std::size_t i = 0; i < p.size(); ++i)
    p.scalar(h)[i] = 0.01 * (i + 1);
  io::write_vtp(dir / "h.vtp", io::particle_point_set(p, 0.0, 99.0, h));
  const Vtp v = read_vtp(dir / "h.vtp");
  EXPECT_FALSE(v.arrays.count("h"));
  for (std::size_t i = 0; i < p.size(); ++i)
    EXPECT_EQ(v.arrays.at("smoothing_length")[i], 0.01 * (i + 1));
  fs::remove_all(dir);
}

TEST(ParticleSnapshot, MismatchedArrayThrows) {
  const fs::path dir = fresh_dir("bad");
  io::PointSet s;
  s.points = {0, 0, 0, 1, 1, 1};
  s.arrays.push_back({"p", 1, {1.0}, {}, {}});
  EXPECT_THROW(io::write_vtp(dir / "bad.vtp", s), std::runtime_error);
  s.arrays[0] = {"p", 1, {1.0, 2.0}, {}, {1, 2}}; // two value types
  EXPECT_THROW(io::write_vtp(dir / "bad.vtp", s), std::runtime_error);
  fs::remove_all(dir);
}

namespace {
// Steps of 0.034 from t = 0 to 0.34 with an interval of 0.1: snapshots at 0 (the initial state),
// 0.102, 0.204, 0.306 (the first steps at or past 0.1, 0.2, 0.3) and the final 0.34.
std::vector<double> run_series(const fs::path& dir, Particles<2>& p, long from_step) {
  io::ParticleSnapshots<2> snaps(dir, 0.1, p, -1, 0.01, 0.034 * from_step, from_step);
  for (long k = from_step + 1; k <= 10; ++k) {
    p.r[0][0] += 1.0; // a visible change per step
    snaps.after_step(0.034 * k, k);
  }
  snaps.final_state(0.034 * 10, 10);
  std::vector<double> t;
  for (const auto& e : io::read_pvd(dir / "particles.pvd"))
    t.push_back(e.time);
  return t;
}
} // namespace

TEST(ParticleSnapshot, SeriesTimesFinalStateAndResume) {
  const fs::path dir = fresh_dir("series");
  Particles<2> p = sample_particles<2>();
  const std::vector<double> t = run_series(dir, p, 0);
  ASSERT_EQ(t.size(), 5u);
  const double want[] = {0.0, 0.034 * 3, 0.034 * 6, 0.034 * 9, 0.034 * 10};
  for (int k = 0; k < 5; ++k)
    EXPECT_DOUBLE_EQ(t[k], want[k]);
  for (int k = 0; k < 5; ++k)
    EXPECT_EQ(read_vtp(dir / io::read_pvd(dir / "particles.pvd")[k].file).time, t[k]);

  // Resumed from a checkpoint of step 7 (t = 0.238) after an attempt that had gone on to the end:
  // the snapshots up to 0.238 stay, the later ones are written again, the same list results.
  Particles<2> q = sample_particles<2>();
  q.r[0][0] += 7.0;
  EXPECT_EQ(run_series(dir, q, 7), t);
  EXPECT_EQ(read_vtp(dir / "particles/particles_000004.vtp").arrays.at("Points")[0],
            p.r[0][0]); // the same final state

  // A final state that is also the last interval's snapshot is written once; interval 0: the final
  // state only; a fresh run clears the snapshots of an earlier one.
  {
    io::ParticleSnapshots<2> snaps(dir, 0.0, p, -1, 0.01, 0.0, 0);
    EXPECT_FALSE(fs::exists(dir / "particles" / "particles_000001.vtp"));
    snaps.after_step(0.5, 1);
    snaps.final_state(0.5, 1);
    snaps.final_state(0.5, 1);
  }
  EXPECT_EQ(io::read_pvd(dir / "particles.pvd").size(), 1u);
  // An interval far below the step: every step once (not 3e7 increments per step).
  {
    io::ParticleSnapshots<2> snaps(dir, 1e-9, p, -1, 0.01, 0.0, 0);
    for (long k = 1; k <= 3; ++k)
      snaps.after_step(0.034 * k, k);
    snaps.final_state(0.034 * 3, 3);
  }
  EXPECT_EQ(io::read_pvd(dir / "particles.pvd").size(), 4u);
  // No output directory: nothing is written.
  io::ParticleSnapshots<2> none("", 0.1, p, -1, 0.01, 0.0, 0);
  none.after_step(0.2, 1);
  none.final_state(0.2, 1);
  fs::remove_all(dir);
}

namespace {

Params defaults(const std::string& case_name, const std::string& scheme) {
  Params prm;
  for (const auto& sp : find_case(case_name)->params)
    prm[sp.name] = sp.default_value;
  for (const auto& sp : find_scheme(scheme)->params)
    prm.emplace(sp.name, sp.default_value);
  prm["scheme"] = scheme;
  return prm;
}

// The cost metrics scripts/regression.sh leaves out (clock readings and their ratios).
bool is_cost(const std::string& m) {
  const auto ends = [&](const std::string& s) {
    return m.size() >= s.size() && m.compare(m.size() - s.size(), s.size(), s) == 0;
  };
  return m.find("wall") != std::string::npos || m.find("cpu") != std::string::npos ||
         m.rfind("time_", 0) == 0 || ends("_s") || m.find("_s_per_") != std::string::npos ||
         m.find("_us_") != std::string::npos || m.find("share") != std::string::npos;
}

// Runs a case twice, without and with an output directory, checks the metrics agree to the bit
// (costs aside) and returns the snapshot series' entries.
std::vector<io::SeriesEntry> run_with_snapshots(const std::string& case_name, const Params& prm,
                                                const fs::path& dir, RunResult& with) {
  const RunResult without = find_case(case_name)->run(prm, RunContext{});
  RunContext ctx;
  ctx.output_dir = dir;
  ctx.job_key = "0123abcd";
  with = find_case(case_name)->run(prm, ctx);
  EXPECT_EQ(with.status, RunStatus::Done) << with.message;
  EXPECT_EQ(with.metrics.size(), without.metrics.size());
  for (std::size_t k = 0; k < with.metrics.size() && k < without.metrics.size(); ++k) {
    EXPECT_EQ(with.metrics[k].first, without.metrics[k].first);
    if (!is_cost(with.metrics[k].first))
      EXPECT_EQ(with.metrics[k].second, without.metrics[k].second) << with.metrics[k].first;
  }
  return io::read_pvd(dir / "particles.pvd");
}

double metric(const RunResult& r, const std::string& k) {
  for (const auto& [n, v] : r.metrics)
    if (n == k)
      return v;
  return std::nan("");
}

// The class and, for a string, the value of a root attribute of an HDF5 file.
H5T_class_t attribute_class(const fs::path& file, const char* key, std::string* text = nullptr) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  const hid_t a = H5Aopen(f, key, H5P_DEFAULT);
  if (a < 0) {
    H5Fclose(f);
    return H5T_NO_CLASS;
  }
  const hid_t t = H5Aget_type(a);
  const H5T_class_t c = H5Tget_class(t);
  if (text && c == H5T_STRING && H5Tis_variable_str(t) > 0) {
    char* s = nullptr;
    H5Aread(a, t, &s);
    *text = s ? s : "";
    H5free_memory(s);
  }
  H5Tclose(t);
  H5Aclose(a);
  H5Fclose(f);
  return c;
}

} // namespace

// Taylor-Green (2D, every particle fluid): n_side^2 points in every snapshot, the initial state,
// one snapshot per output interval and the final state at t_end; the metrics are those of a run
// without outputs. Its HDF5 file keeps its series and carries typed attributes and the job key.
TEST(ParticleSnapshot, TaylorGreenSeriesFromTheTimeLoop) {
  const fs::path dir = fresh_dir("tgv");
  Params prm = defaults("taylor_green", "wcsph_tvf");
  const int n = 20;
  prm["n_side"] = std::int64_t{n};
  prm["t_end"] = 0.1;
  prm["perturb"] = 0.1;
  prm["output_interval"] = 0.025;
  RunResult r;
  const auto e = run_with_snapshots("taylor_green", prm, dir, r);
  ASSERT_EQ(e.size(), 5u); // 0, ~0.025, ~0.05, ~0.075, 0.1 (the last interval's is the final one)
  EXPECT_EQ(e.front().time, 0.0);
  EXPECT_NEAR(e.back().time, 0.1, 1e-12);
  for (std::size_t k = 1; k < e.size(); ++k) {
    EXPECT_GT(e[k].time, e[k - 1].time);
    EXPECT_GE(e[k].time, 0.025 * static_cast<double>(k) * (1 - 1e-12));
  }
  for (const auto& s : e) {
    const Vtp v = read_vtp(dir / s.file);
    EXPECT_EQ(v.points, static_cast<std::size_t>(n * n)) << s.file;
    EXPECT_EQ(v.time, s.time);
  }
  EXPECT_EQ(metric(r, "n_particles"), n * n);
  // Typed attributes: an Int parameter as an integer, a Real as a double, a String as a string.
  const fs::path h5 = dir / "taylor_green.h5";
  std::string key, tvf;
  EXPECT_EQ(attribute_class(h5, "n_side"), H5T_INTEGER);
  EXPECT_EQ(attribute_class(h5, "seed"), H5T_INTEGER);
  EXPECT_EQ(attribute_class(h5, "Re"), H5T_FLOAT);
  EXPECT_EQ(attribute_class(h5, "tvf", &tvf), H5T_STRING);
  EXPECT_EQ(tvf, std::get<std::string>(prm.at("tvf")));
  EXPECT_EQ(attribute_class(h5, "job_key", &key), H5T_STRING);
  EXPECT_EQ(key, "0123abcd");
  EXPECT_EQ(attribute_class(h5, "kernel_correction"), H5T_ENUM); // Bool: h5py's bool enum
  fs::remove_all(dir);
}

// The 3D cavity (fluid and wall particles, z in use): with output_interval 0 only the final state,
// holding every particle of both kinds.
TEST(ParticleSnapshot, Cavity3DFinalStateHoldsEveryKind) {
  const fs::path dir = fresh_dir("cav3d");
  Params prm = defaults("lid_driven_cavity_3d", "wcsph_tvf");
  prm["dx"] = 0.125;
  prm["t_end"] = 0.02;
  RunResult r;
  const auto e = run_with_snapshots("lid_driven_cavity_3d", prm, dir, r);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NEAR(e[0].time, 0.02, 1e-12);
  const Vtp v = read_vtp(dir / e[0].file);
  EXPECT_EQ(static_cast<double>(v.points), metric(r, "n_particles"));
  std::size_t fluid = 0, wall = 0;
  for (double k : v.arrays.at("kind"))
    fluid += k == 0.0, wall += k == 1.0;
  EXPECT_EQ(fluid, 8u * 8u * 8u); // (1 / dx)^3
  EXPECT_GT(wall, 0u);
  EXPECT_EQ(fluid + wall, v.points);
  double zmax = 0.0;
  for (std::size_t i = 0; i < v.points; ++i)
    zmax = std::max(zmax, v.arrays.at("Points")[3 * i + 2]);
  EXPECT_GT(zmax, 0.9);
  EXPECT_EQ(attribute_class(dir / "lid_driven_cavity_3d.h5", "t_stop"), H5T_FLOAT);
  fs::remove_all(dir);
}
