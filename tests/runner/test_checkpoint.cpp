// Checkpoints: the io::Checkpointer round trip, a cancelled checkpoint_demo job resumed to the same
// bits as an uninterrupted run, and the runner killed (SIGKILL) in the middle of a long job: the
// re-run resumes from the checkpoint in the job's output directory, its metrics equal an
// uninterrupted run's bit for bit, and its progress fraction was visible while it ran. A
// checkpoint of other solver code (another fingerprint), a damaged one (SHA-256) and an
// unreadable one are not continued: the job starts again from t = 0 and says why.
#include "e2e_helpers.hpp"

#include "cases/case.hpp"
#include "cases/time_loop.hpp"
#include "core/fingerprint.hpp"
#include "io/checkpoint.hpp"
#include "io/hdf5.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <thread>

using namespace sph;
using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

Params demo_params(std::int64_t steps, std::int64_t sleep_us = 0) {
  const CaseInfo* c = find_case("checkpoint_demo");
  Params p;
  for (const auto& s : c->params)
    p[s.name] = s.default_value;
  p["steps"] = steps;
  p["step_sleep_us"] = sleep_us;
  return p;
}

// Every default of a case and of one of its schemes (default: its first).
Params case_defaults(const std::string& name, std::string scheme = "") {
  const CaseInfo* c = find_case(name);
  EXPECT_NE(c, nullptr);
  if (scheme.empty())
    scheme = c->schemes.at(0);
  Params p;
  for (const auto& s : c->params)
    p[s.name] = s.default_value;
  for (const auto& s : find_scheme(scheme)->params)
    p[s.name] = s.default_value;
  p["scheme"] = scheme;
  return p;
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Metrics of the only job in a database, as stored (doubles, not text).
std::map<std::string, double> metric_values(const fs::path& db) {
  Db d(db.string(), SQLITE_OPEN_READONLY);
  Stmt s = d.prepare("SELECT metric, value FROM job_metrics");
  std::map<std::string, double> out;
  while (s.step())
    out[s.text(0)] = s.real(1);
  return out;
}

} // namespace

TEST(Checkpoint, RoundTripIsExact) {
  TempDir dir;
  io::Checkpointer ck(dir / "out", 10, 0);
  EXPECT_FALSE(ck.load({"x"}).has_value());
  EXPECT_FALSE(ck.due(5));
  EXPECT_TRUE(ck.due(20));
  io::CheckpointState s{42, 0.1 + 0.2, {{"x", {1.0 / 3.0, -0.0, 1e-310, 6.02e23}}}};
  ck.save(s);
  auto r = ck.load({"x"});
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->step, 42);
  EXPECT_TRUE(same_bits(r->time, 0.1 + 0.2));
  ASSERT_EQ(r->arrays["x"].size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_TRUE(same_bits(r->arrays["x"][i], s.arrays["x"][i]));
  EXPECT_FALSE(fs::exists(dir / "out" / "checkpoint.h5.tmp"));
  EXPECT_THROW(ck.load({"missing"}), std::runtime_error);
  ck.discard();
  EXPECT_FALSE(ck.load({"x"}).has_value());
  io::Checkpointer off("", 1, 1);
  EXPECT_FALSE(off.due(1));
}

// Runs case `name` uninterrupted, then cancelled at `cancel_at` of its simulated time (with a
// checkpoint every `every` steps) and resumed: every metric not in `costs` (wall-clock and CPU
// measurements) must be the same bits. Returns the resumed run's message.
std::string expect_resume_is_exact(const std::string& name, const Params& p, double cancel_at,
                                   std::int64_t every, const std::set<std::string>& costs = {}) {
  const CaseInfo* c = find_case(name);
  EXPECT_NE(c, nullptr);
  RunContext plain;
  RunResult ref = c->run(p, plain);
  EXPECT_EQ(ref.status, RunStatus::Done);

  TempDir dir;
  std::atomic<bool> cancel{false};
  RunContext ctx;
  ctx.checkpoint_dir = dir / "job";
  ctx.checkpoint_every_steps = every;
  ctx.cancel = &cancel;
  ctx.progress = [&](double f) {
    if (f >= cancel_at)
      cancel = true;
  };
  RunResult first = c->run(p, ctx);
  EXPECT_EQ(first.status, RunStatus::Cancelled);
  EXPECT_TRUE(fs::exists(dir / "job" / "checkpoint.h5"));

  cancel = false;
  ctx.progress = nullptr;
  ctx.attempt = 2;
  RunResult second = c->run(p, ctx);
  EXPECT_EQ(second.status, RunStatus::Done);
  EXPECT_EQ(second.metrics.size(), ref.metrics.size());
  for (std::size_t i = 0; i < std::min(ref.metrics.size(), second.metrics.size()); ++i) {
    EXPECT_EQ(second.metrics[i].first, ref.metrics[i].first);
    if (costs.count(ref.metrics[i].first))
      continue;
    EXPECT_TRUE(same_bits(second.metrics[i].second, ref.metrics[i].second))
        << ref.metrics[i].first << ": " << second.metrics[i].second << " vs "
        << ref.metrics[i].second;
  }
  EXPECT_FALSE(fs::exists(dir / "job" / "checkpoint.h5")); // discarded once final
  return second.message;
}

TEST(Checkpoint, CancelledJobResumesToTheSameBits) {
  std::string msg = expect_resume_is_exact("checkpoint_demo", demo_params(3000), 0.45, 1000);
  EXPECT_CONTAINS(msg, "resumed from step 13"); // cancelled at 45%: saved at step 1350
}

// The elastic solid (total-Lagrangian: a neighbour list and correction matrices of the reference
// configuration, rebuilt from the saved reference positions on resume) under its own weight.
TEST(Checkpoint, CantileverResumesToTheSameBits) {
  Params p = case_defaults("cantilever");
  p["L"] = 0.1;
  p["H"] = 0.02;
  p["H_over_dx"] = std::int64_t{4};
  p["t_end"] = 0.02;
  std::string msg = expect_resume_is_exact("cantilever", p, 0.5, 50,
                                           {"wall_time_s", "time_per_step_s", "cpu_time_per_step_s",
                                            "cpu_time_s", "time_per_particle_step_s"});
  EXPECT_CONTAINS(msg, "resumed at t = ");
}

// The FSI beam (issue 18): the fluid with its inflow and outflow buffers, the solid's own particle
// set, scheme state and averaged velocity (saved by the case), the tip and force series.
TEST(Checkpoint, FsiBeamResumesToTheSameBits) {
  Params p = case_defaults("fsi_beam");
  p["H_over_dx"] = std::int64_t{2};
  p["t_end"] = 0.1;
  p["ramp_time"] = 0.5;
  p["settle_fraction"] = 0.0;
  std::string msg = expect_resume_is_exact("fsi_beam", p, 0.5, 10,
                                           {"wall_time_s", "time_per_step_s", "cpu_time_per_step_s",
                                            "cpu_time_s", "time_per_particle_step_s"});
  EXPECT_CONTAINS(msg, "resumed at t = ");
}

// A real scheme: the transport-velocity WCSPH Taylor-Green vortex (particles re-sorted by cell
// every step, dual-criteria time steps) resumes from its checkpoint to the same bits.
TEST(Checkpoint, TaylorGreenResumesToTheSameBits) {
  Params p = case_defaults("taylor_green");
  p["n_side"] = std::int64_t{20};
  p["t_end"] = 0.2;
  p["tvf"] = std::string("limited");
  p["perturb"] = 0.3;
  std::string msg = expect_resume_is_exact(
      "taylor_green", p, 0.5, 7,
      {"wall_s", "time_per_particle_step_s", "time_per_particle_adv_step_s", "cpu_s", "wall_time_s",
       "time_per_step_s", "cpu_time_per_step_s", "cpu_time_s"});
  EXPECT_CONTAINS(msg, "resumed at t = ");
}

// The ISPH lid-driven cavity (the longest jobs of the project: about an hour at dx = 0.01): the
// PPE's warm start, the steady-state window and the E_k history come back with the particles.
TEST(Checkpoint, IsphCavityResumesToTheSameBits) {
  Params p = case_defaults("lid_driven_cavity");
  p["dx"] = 0.05;
  p["t_end"] = 0.3;
  p["steady_window"] = 0.05; // several windows, one of them split by the checkpoint
  p["history_interval"] = 0.02;
  std::string msg = expect_resume_is_exact(
      "lid_driven_cavity", p, 0.5, 70,
      {"wall_time_s", "time_per_step_s", "cpu_time_per_step_s", "cpu_time_s",
       "ppe_assembly_s_per_step", "ppe_solve_s_per_step", "ppe_share", "time_per_particle_step_s"});
  EXPECT_CONTAINS(msg, "resumed at t = 0.15 "); // cancelled at the first step after 50 %
}

// The same cavity with the transport-velocity WCSPH (dual-criteria steps of varying size).
TEST(Checkpoint, WcsphTvfCavityResumesToTheSameBits) {
  Params p = case_defaults("lid_driven_cavity", "wcsph_tvf");
  p["dx"] = 0.05;
  p["Re"] = 1000.0;
  p["t_end"] = 0.5;
  p["steady_window"] = 0.1;
  p["history_interval"] = 0.05;
  std::string msg = expect_resume_is_exact("lid_driven_cavity", p, 0.5, 11,
                                           {"wall_time_s", "time_per_step_s", "cpu_time_per_step_s",
                                            "cpu_time_s", "time_per_particle_step_s"});
  EXPECT_CONTAINS(msg, "resumed at t = 0.25");
}

// ALSPH flow past a cylinder: the particle count changes every step (inflow, outflow, mirror
// ghosts), and the force series and averaging sums are part of the state. Both algorithms.
TEST(Checkpoint, AlsphCylinderChannelResumesToTheSameBits) {
  for (std::int64_t algorithm : {1, 2}) {
    Params p = case_defaults("cylinder_channel");
    p["algorithm"] = algorithm;
    p["D_over_dx"] = 6.0; // the studies' quick tier
    p["channel_length"] = 6.0;
    p["channel_height"] = 4.0;
    p["upstream_length"] = 2.0;
    p["dt_star"] = 2.54e-2;
    p["t_end"] = 0.25; // 60 steps; averages over the last 30
    std::string msg = expect_resume_is_exact(
        "cylinder_channel", p, 0.7, 9, // cancelled after the settling time: the sums are running
        {"wall_s", "cpu_s", "wall_time_s", "time_per_step_s", "cpu_time_per_step_s", "cpu_time_s",
         "time_per_particle_step_s", "search_cpu_us_per_particle", "shifting_cpu_us_per_particle",
         "cpu_us_per_particle_step", "iteration_cpu_us_per_particle", "refresh_cpu_us_per_particle",
         "search_over_iteration"});
    EXPECT_CONTAINS(msg, "resumed at t = 0.1778") << "algorithm " << algorithm;
  }
}

// Contact SPH shear layer (the godunov studies' jobs, up to 20 min): particles and their mirror
// ghosts, the cell radius, and the erf fits already made at 0.6 and 0.7 t_end.
TEST(Checkpoint, ContactShearLayerResumesToTheSameBits) {
  Params p = case_defaults("shear_layer");
  p["dim"] = std::int64_t{2}; // the godunov_zeta quick tier
  p["nx"] = std::int64_t{40};
  p["ny"] = std::int64_t{8};
  p["t_end"] = 3e-10;
  p["zeta"] = 1.0;
  std::string msg =
      expect_resume_is_exact("shear_layer", p, 0.75, 40,
                             {"wall_s", "wall_per_step_s", "wall_time_s", "time_per_step_s",
                              "cpu_time_per_step_s", "cpu_time_s", "time_per_particle_step_s"});
  EXPECT_CONTAINS(msg, "resumed at t = 2.2");
}

// Study files of one checkpoint_demo job: slow.toml (600 steps x 5 ms = 3 s) and fast.toml, the
// same job without the pause (step_sleep_us is not part of the job key, so both have the same
// key and must give the same bits).
void write_demo_studies(const TempDir& dir) {
  write_text(dir / "slow.toml", R"([study]
name = "ckpt"
case = "checkpoint_demo"
[params]
steps = 600
step_sleep_us = 5000
)");
  write_text(dir / "fast.toml", R"([study]
name = "ckpt"
case = "checkpoint_demo"
[params]
steps = 600
)");
}

// Starts `runner slow.toml` (checkpoints every 100 steps) with `env`, waits until its job has
// run past a quarter (progress in the database) with a checkpoint on disk, calls before_kill and
// SIGKILLs the runner. Returns the job key ("" when that did not happen within 20 s).
std::string
kill_runner_after_a_checkpoint(const TempDir& dir,
                               const std::vector<std::pair<std::string, std::string>>& env,
                               const std::function<void()>& before_kill = {}) {
  fs::path db = dir / "results" / "results.sqlite";
  pid_t pid = spawn_runner(dir.path(),
                           {"slow.toml", "--checkpoint-every-steps", "100", "--heartbeat-s", "0.2"},
                           env, dir / "bg.txt");
  EXPECT_GT(pid, 0);
  std::string key;
  double progress_seen = -1;
  bool ready = false;
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!ready && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    try {
      if (!fs::exists(db))
        continue;
      key = sql_text(db, "SELECT key FROM jobs");
      if (!key.empty())
        key.pop_back();
      std::string pr = sql_text(db, "SELECT progress FROM jobs WHERE state='running'");
      if (!pr.empty() && pr != "\n")
        progress_seen = std::stod(pr);
      ready = !key.empty() && progress_seen > 0.25 &&
              fs::exists(dir / "results" / "ckpt" / key / "checkpoint.h5");
    } catch (...) {
    }
  }
  EXPECT_TRUE(ready) << "no checkpoint and progress > 0.25 of a running job within 20 s "
                     << "(progress seen: " << progress_seen << ")";
  if (ready && before_kill)
    before_kill();
  ::kill(pid, SIGKILL);
  wait_exit(pid);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  return ready ? key : "";
}

// The metrics of the only job of dir's database against an uninterrupted run of fast.toml.
void expect_metrics_of_an_uninterrupted_run(const TempDir& dir) {
  auto ref = run_runner(dir, "fast.toml --db ref/results.sqlite");
  ASSERT_EQ(ref.code, 0) << ref.out;
  auto got = metric_values(dir / "results" / "results.sqlite"),
       reference = metric_values(dir / "ref" / "results.sqlite");
  ASSERT_EQ(got.size(), 5u);
  ASSERT_EQ(reference.size(), got.size());
  for (const auto& [name, value] : reference)
    EXPECT_TRUE(same_bits(got[name], value))
        << name << ": resumed " << got[name] << " vs uninterrupted " << value;
}

// The runner is SIGKILLed while a long job runs (after its first checkpoints); the next run
// resumes the job from its checkpoint instead of starting over.
TEST(Checkpoint, RunnerKilledMidJobResumesFromTheCheckpoint) {
  TempDir dir;
  write_demo_studies(dir);
  fs::path db = dir / "results" / "results.sqlite";
  std::string key = kill_runner_after_a_checkpoint(dir, {}, [&] {
    auto st = run_runner(dir, "status ckpt", "", "status.txt");
    EXPECT_CONTAINS(st.out, "running jobs:");
    EXPECT_CONTAINS(st.out, "%");
  });
  ASSERT_FALSE(key.empty()) << "the running job's progress reached the database";
  ASSERT_TRUE(fs::exists(dir / "results" / "ckpt" / key / "checkpoint.h5"));

  auto r = run_runner(dir, "slow.toml --checkpoint-every-steps 100");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='done' AND attempt=2 AND "
                        "message LIKE 'resumed from step %'"),
            1)
      << sql_text(db, "SELECT attempt, state, message, error_text FROM attempts");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='abandoned' AND "
                        "failure_class='stale'"),
            1);
  expect_metrics_of_an_uninterrupted_run(dir);
}

// A job killed under one build and run again by a build of other solver code (another solver
// fingerprint: SPH_RUNNER_SOLVER_FINGERPRINT) starts again from t = 0, saying so with both
// fingerprints; its result is the uninterrupted run's and is recorded under the new fingerprint.
TEST(Checkpoint, AnotherBuildsCheckpointIsNotContinued) {
  TempDir dir;
  write_demo_studies(dir);
  fs::path db = dir / "results" / "results.sqlite";
  std::string key =
      kill_runner_after_a_checkpoint(dir, {{"SPH_RUNNER_SOLVER_FINGERPRINT", "aaaa1111"}});
  ASSERT_FALSE(key.empty());
  auto r = run_runner(dir, "slow.toml --checkpoint-every-steps 100",
                      "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb2222");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string msg =
      sql_text(db, "SELECT message FROM attempts WHERE attempt=2 AND state='done'");
  EXPECT_CONTAINS(msg, "written by solver fingerprint aaaa1111, not by this build's bbbb2222");
  EXPECT_CONTAINS(msg, "restarted from t = 0");
  EXPECT_EQ(msg.find("resumed"), std::string::npos) << msg;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='done' AND "
                        "solver_fingerprint='bbbb2222'"),
            1);
  expect_metrics_of_an_uninterrupted_run(dir);
}

// One flipped bit in a state value of checkpoint.h5: the checkpoint fails its SHA-256, is
// removed, and the job starts again from t = 0 (the uninterrupted run's bits, not a result of
// the damaged state).
TEST(Checkpoint, ADamagedCheckpointIsDiscardedAndTheJobRestarts) {
  TempDir dir;
  write_demo_studies(dir);
  fs::path db = dir / "results" / "results.sqlite";
  std::string key = kill_runner_after_a_checkpoint(dir, {});
  ASSERT_FALSE(key.empty());
  const fs::path ck = dir / "results" / "ckpt" / key / "checkpoint.h5";
  // The bytes of x[5] in the file: its lowest mantissa bit flipped.
  const std::vector<double> x = io::read_dataset(ck, "state/x");
  ASSERT_GT(x.size(), 5u);
  std::string bytes = read_file(ck);
  const std::size_t at = bytes.find(std::string(reinterpret_cast<const char*>(&x[5]), 8));
  ASSERT_NE(at, std::string::npos);
  bytes[at] = static_cast<char>(bytes[at] ^ 1);
  std::ofstream(ck, std::ios::binary | std::ios::trunc) << bytes;
  ASSERT_NE(io::read_dataset(ck, "state/x")[5], x[5]);

  auto r = run_runner(dir, "slow.toml --checkpoint-every-steps 100");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string msg =
      sql_text(db, "SELECT message FROM attempts WHERE attempt=2 AND state='done'");
  EXPECT_CONTAINS(msg, "the checkpoint failed its SHA-256 check");
  EXPECT_CONTAINS(msg, "restarted from t = 0");
  expect_metrics_of_an_uninterrupted_run(dir);
}

// A checkpoint that is not an HDF5 file at all (or a truncated one) does not fail the job: it is
// removed with a message and the job starts again from t = 0.
TEST(Checkpoint, AnUnreadableCheckpointIsDiscardedAndTheJobRestarts) {
  TempDir dir;
  write_demo_studies(dir);
  fs::path db = dir / "results" / "results.sqlite";
  std::string key = kill_runner_after_a_checkpoint(dir, {});
  ASSERT_FALSE(key.empty());
  const fs::path ck = dir / "results" / "ckpt" / key / "checkpoint.h5";
  const std::string bytes = read_file(ck);
  std::ofstream(ck, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() / 2);

  auto r = run_runner(dir, "slow.toml --checkpoint-every-steps 100");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(sql_text(db, "SELECT state FROM jobs"), "done\n");
  const std::string msg =
      sql_text(db, "SELECT message FROM attempts WHERE attempt=2 AND state='done'");
  EXPECT_CONTAINS(msg, "the checkpoint could not be read");
  EXPECT_CONTAINS(msg, "restarted from t = 0");
  expect_metrics_of_an_uninterrupted_run(dir);
}

// In the solver's time loop (a real case): a checkpoint written by other solver code with a
// valid checksum, whose state is altered, is not continued; the run equals an uninterrupted one.
TEST(Checkpoint, TheTimeLoopRestartsFromAnotherBuildsCheckpoint) {
  Params p = case_defaults("taylor_green");
  p["n_side"] = std::int64_t{20};
  p["t_end"] = 0.2;
  const CaseInfo* c = find_case("taylor_green");
  RunContext plain;
  RunResult ref = c->run(p, plain);
  ASSERT_EQ(ref.status, RunStatus::Done);

  TempDir dir;
  std::atomic<bool> cancel{false};
  RunContext ctx;
  ctx.checkpoint_dir = dir / "job";
  ctx.checkpoint_every_steps = 7;
  ctx.cancel = &cancel;
  ctx.progress = [&](double f) {
    if (f >= 0.5)
      cancel = true;
  };
  ASSERT_EQ(c->run(p, ctx).status, RunStatus::Cancelled);
  // The same state under another fingerprint (a correct checksum), its velocities doubled: a
  // continuation would end elsewhere.
  const fs::path file = dir / "job" / "checkpoint.h5";
  std::vector<std::string> names;
  {
    std::istringstream listed(*io::read_string_attribute(file, "state_arrays"));
    for (std::string n; std::getline(listed, n);)
      names.push_back(n);
  }
  io::Checkpointer mine(dir / "job");
  auto st = mine.load(names);
  ASSERT_TRUE(st.has_value()) << mine.rejection();
  ASSERT_TRUE(st->arrays.count("p/v"));
  for (double& v : st->arrays["p/v"])
    v *= 2;
  io::Checkpointer(dir / "job", 0, 0, "0123456789abcdef").save(*st);

  cancel = false;
  ctx.progress = nullptr;
  ctx.attempt = 2;
  RunResult second = c->run(p, ctx);
  ASSERT_EQ(second.status, RunStatus::Done);
  EXPECT_CONTAINS(second.message, "written by solver fingerprint 0123456789abcdef, not by this "
                                  "build's " +
                                      solver_fingerprint());
  EXPECT_CONTAINS(second.message, "restarted from t = 0");
  const std::set<std::string> costs{
      "wall_s", "time_per_particle_step_s", "wall_time_s", "time_per_particle_adv_step_s",
      "cpu_s",  "time_per_step_s",          "cpu_time_s",  "cpu_time_per_step_s"};
  ASSERT_EQ(second.metrics.size(), ref.metrics.size());
  for (std::size_t i = 0; i < ref.metrics.size(); ++i)
    if (!costs.count(ref.metrics[i].first))
      EXPECT_TRUE(same_bits(second.metrics[i].second, ref.metrics[i].second))
          << ref.metrics[i].first;
}

// Contact SPH flow through the cylinder array (the godunov_cylinders quick tier, corrected):
// the body-force drive, the solid wall pairs and the superficial velocities sampled at 0.8 and
// 0.9 t_end before the cancellation at 0.95.
TEST(Checkpoint, ContactCylinderArrayResumesToTheSameBits) {
  Params p = case_defaults("cylinder_array");
  p["n_d"] = std::int64_t{8};
  p["t_end_visc"] = 0.02;
  p["zeta"] = 1.0;
  std::string msg =
      expect_resume_is_exact("cylinder_array", p, 0.95, 50,
                             {"wall_s", "wall_per_step_s", "wall_time_s", "time_per_step_s",
                              "cpu_time_per_step_s", "cpu_time_s", "time_per_particle_step_s"});
  EXPECT_CONTAINS(msg, "resumed at t = ");
}

// Open boundaries (issue 19): the particle count and kinds change every few steps (emitter,
// disposer), the free-stream surface indicator of the last step is a particle field; the masses
// in and out and the next particle id are the case's state. The empty free-stream box (a
// perturbed start, so the fields are not uniform) and the cylinder with boundary = free_stream.
TEST(Checkpoint, OpenBoundariesResumeToTheSameBits) {
  const std::set<std::string> costs{"wall_s",          "time_per_particle_step_s", "wall_time_s",
                                    "time_per_step_s", "cpu_time_per_step_s",      "cpu_time_s"};
  Params b = case_defaults("free_stream_box");
  b["t_end"] = 3.0, b["perturb"] = 0.5, b["settle_fraction"] = 0.3;
  EXPECT_CONTAINS(expect_resume_is_exact("free_stream_box", b, 0.5, 17, costs), "resumed at t = ");
  Params c = case_defaults("cylinder_free_stream");
  c["D_over_dx"] = 5.0, c["t_end"] = 3.0, c["ramp_time"] = 1.0, c["sample_interval"] = 0.1;
  c["boundary"] = std::string("free_stream"), c["domain_length"] = 12.0;
  c["domain_height"] = 6.0, c["upstream_length"] = 4.0;
  EXPECT_CONTAINS(expect_resume_is_exact("cylinder_free_stream", c, 0.5, 13, costs),
                  "resumed at t = ");
  // The 3D nozzle: emitter over the inlet's rings, the outlet buffer moving with the fluid, the
  // flux window's start; a short nozzle at Re_throat = 2000 so that slices are emitted and disposed
  // of within the run (4 and 6 mm of pipe around the throat, 8 ms).
  Params n = case_defaults("fda_nozzle");
  n["dx"] = 0.001, n["upstream_length"] = 0.004, n["downstream_length"] = 0.006;
  n["Re_throat"] = 2000.0, n["ramp_time"] = 0.002, n["t_end"] = 0.008, n["flux_window"] = 0.005;
  EXPECT_CONTAINS(expect_resume_is_exact("fda_nozzle", n, 0.5, 11, costs), "resumed at t = ");
  // With two resolution levels (issue 19 section 2): the h field and the split/merge counters are
  // state (the levels keep nothing else). No particle crosses the band's edges within these 3 D/U
  // (checked: both counters 0), so this pins the two-level fill, emitters and state layout, not a
  // resume across a split.
  c["refinement_band"] = 1.2;
  EXPECT_CONTAINS(expect_resume_is_exact("cylinder_free_stream", c, 0.5, 13, costs),
                  "resumed at t = ");
}

// The wcsph_tvf cylinder: the force series, the partial sample bin and the symmetry nudge's flag.
TEST(Checkpoint, CylinderFreeStreamResumesToTheSameBits) {
  Params p = case_defaults("cylinder_free_stream");
  p["D_over_dx"] = 5.0;
  p["t_end"] = 3.0;
  p["ramp_time"] = 1.0;
  p["sample_interval"] = 0.1;
  for (double band : {0.0, 2.0}) { // uniform, and variable resolution (the h field)
    p["refinement_band"] = band;
    std::string msg =
        expect_resume_is_exact("cylinder_free_stream", p, 0.5, 13,
                               {"wall_s", "time_per_particle_step_s", "wall_time_s",
                                "time_per_step_s", "cpu_time_per_step_s", "cpu_time_s"});
    EXPECT_CONTAINS(msg, "resumed at t = ");
  }
}

// The message of a diverged run gives its time and speed with 6 significant digits: not
// "t = 0.000000" for a time of 1e-10 s, nor 301 digits for the 1e300 that stands for a speed
// that is not finite (that one reads "velocity not finite").
TEST(TimeLoop, ADivergedRunSaysWhenWithSixSignificantDigits) {
  Params p = case_defaults("lid_driven_cavity");
  p["dx"] = 0.05;
  p["dt"] = 0.05; // far too large: the PPE fails at t = 1.85
  p["t_end"] = 3.0;
  RunContext plain;
  RunResult r = find_case("lid_driven_cavity")->run(p, plain);
  ASSERT_EQ(r.status, RunStatus::Diverged) << r.message;
  EXPECT_CONTAINS(r.message, " at t = 1.85");
  EXPECT_EQ(r.message.find("1.850000"), std::string::npos) << r.message;
  EXPECT_EQ(message_number(1e300), "1e+300");
  EXPECT_EQ(message_number(26.6), "26.6");
  EXPECT_EQ(message_number(3e-10), "3e-10");
}
