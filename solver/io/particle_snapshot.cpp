// VTK XML PolyData snapshots and their ParaView collection (see particle_snapshot.hpp for the
// formats and their references).
#include "io/particle_snapshot.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace sph::io {

namespace {

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& p) {
  throw std::runtime_error("particle snapshot: " + what + " (" + p.string() + ")");
}

// Shortest text that reads back to the same double.
std::string exact(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// XML attribute value: the five predefined entities escaped.
std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s)
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&apos;";
      break;
    default:
      out += c;
    }
  return out;
}

// Writes text (and the raw block) to file.tmp, then renames it to file.
void write_atomic(const std::filesystem::path& file, const std::string& head,
                  const std::vector<std::pair<const void*, std::size_t>>& blocks,
                  const std::string& tail) {
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  if (file.has_parent_path())
    std::filesystem::create_directories(file.parent_path());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      fail("cannot create file", tmp);
    out.write(head.data(), static_cast<std::streamsize>(head.size()));
    for (const auto& [data, bytes] : blocks)
      out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
    out.write(tail.data(), static_cast<std::streamsize>(tail.size()));
    out.flush();
    if (!out)
      fail("cannot write file", tmp);
  }
  std::filesystem::rename(tmp, file);
}

} // namespace

void write_vtp(const std::filesystem::path& file, const PointSet& s) {
  static_assert(sizeof(double) == 8 && sizeof(std::int64_t) == 8);
  {
    const std::uint32_t one = 1;
    unsigned char b;
    std::memcpy(&b, &one, 1);
    if (b != 1)
      fail("big-endian hosts are not supported", file);
  }
  const std::size_t n = s.size();
  if (s.points.size() != 3 * n)
    fail("points: not 3 coordinates per point", file);
  // The appended block: for each array, its size in bytes (UInt64) then its values.
  std::vector<std::pair<const void*, std::size_t>> blocks;
  std::vector<std::uint64_t> sizes; // kept alive: blocks point into it
  sizes.reserve(2 * (s.arrays.size() + 3));
  std::uint64_t offset = 0;
  auto append = [&](const void* data, std::size_t bytes) {
    const std::uint64_t at = offset;
    sizes.push_back(bytes);
    blocks.emplace_back(&sizes.back(), sizeof(std::uint64_t));
    blocks.emplace_back(data, bytes);
    offset += sizeof(std::uint64_t) + bytes;
    return at;
  };
  std::ostringstream x;
  auto data_array = [&](const char* type, const std::string& name, int comps, std::uint64_t at) {
    x << "        <DataArray type=\"" << type << "\" Name=\"" << xml_escape(name)
      << "\" NumberOfComponents=\"" << comps << "\" format=\"appended\" offset=\"" << at
      << "\"/>\n";
  };
  x << "<?xml version=\"1.0\"?>\n"
       "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt64\">\n"
       "  <PolyData>\n"
       "    <FieldData>\n"
       "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
       "format=\"ascii\">"
    << exact(s.time)
    << "</DataArray>\n"
       "    </FieldData>\n"
       "    <Piece NumberOfPoints=\""
    << n << "\" NumberOfVerts=\"" << n
    << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
       "      <PointData Scalars=\"pressure\" Vectors=\"velocity\">\n";
  for (const auto& a : s.arrays) {
    if (a.components < 1)
      fail("array " + a.name + ": no components", file);
    const std::size_t want = static_cast<std::size_t>(a.components) * n;
    const int kinds = !a.f64.empty() + !a.i64.empty() + !a.u8.empty();
    if (want > 0 && kinds != 1)
      fail("array " + a.name + ": exactly one value type must hold the values", file);
    if (!a.f64.empty() || (kinds == 0)) {
      if (a.f64.size() != want)
        fail("array " + a.name + ": size does not match the points", file);
      data_array("Float64", a.name, a.components, append(a.f64.data(), 8 * want));
    } else if (!a.i64.empty()) {
      if (a.i64.size() != want)
        fail("array " + a.name + ": size does not match the points", file);
      data_array("Int64", a.name, a.components, append(a.i64.data(), 8 * want));
    } else {
      if (a.u8.size() != want)
        fail("array " + a.name + ": size does not match the points", file);
      data_array("UInt8", a.name, a.components, append(a.u8.data(), want));
    }
  }
  x << "      </PointData>\n      <Points>\n";
  data_array("Float64", "Points", 3, append(s.points.data(), 8 * 3 * n));
  x << "      </Points>\n      <Verts>\n";
  // One vertex cell per point: connectivity 0..n-1, offsets 1..n.
  std::vector<std::int64_t> conn(n), offs(n);
  for (std::size_t i = 0; i < n; ++i)
    conn[i] = static_cast<std::int64_t>(i), offs[i] = static_cast<std::int64_t>(i + 1);
  data_array("Int64", "connectivity", 1, append(conn.data(), 8 * n));
  data_array("Int64", "offsets", 1, append(offs.data(), 8 * n));
  x << "      </Verts>\n"
       "    </Piece>\n"
       "  </PolyData>\n"
       "  <AppendedData encoding=\"raw\">\n   _";
  write_atomic(file, x.str(), blocks, "\n  </AppendedData>\n</VTKFile>\n");
}

void write_pvd(const std::filesystem::path& file, const std::vector<SeriesEntry>& entries) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n"
       "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       "  <Collection>\n";
  for (const auto& e : entries)
    x << "    <DataSet timestep=\"" << exact(e.time) << "\" group=\"\" part=\"0\" file=\""
      << xml_escape(e.file) << "\"/>\n";
  x << "  </Collection>\n</VTKFile>\n";
  write_atomic(file, x.str(), {}, "");
}

std::vector<SeriesEntry> read_pvd(const std::filesystem::path& file) {
  std::vector<SeriesEntry> out;
  std::ifstream in(file);
  if (!in)
    return out;
  static const std::regex entry("<DataSet timestep=\"([^\"]*)\"[^>]* file=\"([^\"]*)\"");
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, entry))
      out.push_back({std::stod(m[1].str()), m[2].str()});
  }
  return out;
}

SnapshotSeries::SnapshotSeries(std::filesystem::path dir, double interval)
    : dir_(std::move(dir)), interval_(interval) {}

void SnapshotSeries::advance_k(double t) {
  if (interval_ <= 0.0)
    return;
  // The first multiple after t, without counting up to it (an interval far below the step).
  const double q = std::floor(t / interval_);
  if (q >= static_cast<double>(next_k_) && q < 1e15)
    next_k_ = static_cast<long>(q);
  while (due(t)) // round-off either way
    ++next_k_;
}

bool SnapshotSeries::due(double t) const {
  if (interval_ <= 0.0)
    return false;
  // The same relative tolerance as FlowScheme::finished: a step that lands on k interval up to
  // round-off counts as reaching it.
  const double tk = static_cast<double>(next_k_) * interval_;
  return t >= tk * (1.0 - 1e-12);
}

bool SnapshotSeries::start(double t, long steps) {
  if (!enabled())
    return false;
  const std::filesystem::path folder = dir_ / "particles";
  if (steps == 0) {
    std::error_code ec;
    std::filesystem::remove_all(folder, ec); // a fresh run: no snapshot of an earlier attempt
    std::filesystem::remove(pvd(), ec);
    entries_.clear();
    next_k_ = 1;
    return interval_ > 0.0;
  }
  // Resumed at time t: keep what was written up to t.
  for (const auto& e : read_pvd(pvd()))
    if (e.time <= t)
      entries_.push_back(e);
  next_k_ = 1;
  advance_k(t);
  if (!entries_.empty() && entries_.back().time == t)
    last_step_ = steps; // the checkpointed state was written: not again as the final state
  write_pvd(pvd(), entries_);
  return false;
}

void SnapshotSeries::write(const PointSet& s, long steps) {
  if (!enabled())
    return;
  char name[64];
  std::snprintf(name, sizeof name, "particles/particles_%06zu.vtp", entries_.size());
  write_vtp(dir_ / name, s);
  entries_.push_back({s.time, name});
  write_pvd(pvd(), entries_);
  last_step_ = steps;
  advance_k(s.time);
}

} // namespace sph::io
