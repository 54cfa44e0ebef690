// checkpoint_demo: a small deterministic time-dependent case for the runner's tests of
// checkpoint/resume and live progress (not an SPH benchmark, so it lives in runner/, not in the
// solver, and keeps its own few-line loop instead of the solver's time loop). A periodic chain of n
// particles coupled by nonlinear (Fermi-Pasta-Ulam-Tsingou alpha) springs, integrated by velocity
// Verlet for `steps` steps. The state (x, v, a) is checkpointed through io::Checkpointer, so a
// killed or cancelled job resumes where it stopped, and its metrics equal an uninterrupted run's
// bit for bit.
#include "cases/case.hpp"
#include "io/checkpoint.hpp"

#include <chrono>
#include <cmath>
#include <thread>

namespace sph {

namespace {

void accelerations(const std::vector<double>& x, double alpha, std::vector<double>& a) {
  const std::size_t n = x.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double left = x[i] - x[(i + n - 1) % n];
    const double right = x[(i + 1) % n] - x[i];
    a[i] = (right - left) + alpha * (right * right - left * left);
  }
}

double energy(const std::vector<double>& x, const std::vector<double>& v, double alpha) {
  const std::size_t n = x.size();
  double e = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = x[(i + 1) % n] - x[i];
    e += 0.5 * v[i] * v[i] + 0.5 * d * d + alpha * d * d * d / 3.0;
  }
  return e;
}

RunResult run_checkpoint_demo(const Params& prm, const RunContext& ctx) {
  const auto n = static_cast<std::size_t>(get_int(prm, "n"));
  const std::int64_t steps = get_int(prm, "steps");
  const double dt = get_real(prm, "dt");
  const double alpha = get_real(prm, "alpha");
  const auto sleep_us = get_int(prm, "step_sleep_us");

  std::vector<double> x(n), v(n, 0.0), a(n);
  for (std::size_t i = 0; i < n; ++i)
    x[i] = std::sin(2 * M_PI * static_cast<double>(i) / static_cast<double>(n)); // lowest mode
  std::int64_t step = 0;
  double t = 0;
  accelerations(x, alpha, a);
  const double e0 = energy(x, v, alpha);

  io::Checkpointer ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s,
                      ctx.fingerprint.empty() ? solver_fingerprint() : ctx.fingerprint);
  RunResult res;
  if (auto s = ck.load({"x", "v", "a"})) {
    step = s->step;
    t = s->time;
    x = s->arrays["x"];
    v = s->arrays["v"];
    a = s->arrays["a"];
    if (x.size() != n || v.size() != n || a.size() != n)
      throw std::runtime_error("checkpoint does not match n=" + std::to_string(n));
    res.message = "resumed from step " + std::to_string(step) + " (attempt " +
                  std::to_string(ctx.attempt) + ")";
  } else {
    res.message = ck.rejection(); // a checkpoint it could not continue: why it started again
  }
  auto save = [&](std::int64_t steps_done) {
    ck.save({steps_done, t, {{"x", x}, {"v", v}, {"a", a}}});
  };
  for (; step < steps; ++step) {
    if (ctx.cancelled()) {
      save(step);
      res.status = RunStatus::Cancelled;
      return res;
    }
    for (std::size_t i = 0; i < n; ++i) {
      v[i] += 0.5 * dt * a[i];
      x[i] += dt * v[i];
    }
    accelerations(x, alpha, a);
    for (std::size_t i = 0; i < n; ++i)
      v[i] += 0.5 * dt * a[i];
    t += dt;
    if (ck.due(step + 1))
      save(step + 1);
    ctx.report(static_cast<double>(step + 1) / static_cast<double>(steps));
    if (sleep_us > 0)
      std::this_thread::sleep_for(std::chrono::microseconds(sleep_us));
  }
  const double e1 = energy(x, v, alpha);
  double checksum = 0;
  for (std::size_t i = 0; i < n; ++i)
    checksum += x[i] * static_cast<double>(i + 1) + v[i];
  res.add("t_end", t);
  res.add("energy", e1);
  res.add("energy_drift", (e1 - e0) / e0);
  res.add("x0", x[0]);
  res.add("checksum", checksum);
  if (!std::isfinite(e1)) {
    res.status = RunStatus::Diverged;
    res.message = "energy is not finite";
  }
  ck.discard(); // the results are final: the checkpoint has served its purpose
  return res;
}

} // namespace

CaseInfo make_checkpoint_demo_case() {
  CaseInfo c;
  c.name = "checkpoint_demo";
  c.test_fixture = true;
  c.description = "test case (not SPH): FPUT-alpha chain, velocity Verlet, checkpointed state";
  c.params = {
      {"n", ParamType::Int, std::int64_t{64}, "particles in the periodic chain", 2.0, 1e6},
      {"steps", ParamType::Int, std::int64_t{2000}, "time steps", 1.0, 1e9},
      {"dt", ParamType::Real, 0.05, "time step", 0.0, 1.0, true},
      {"alpha", ParamType::Real, 0.25, "quadratic spring nonlinearity", 0.0, 10.0},
      {"step_sleep_us",
       ParamType::Int,
       std::int64_t{0},
       "wall-clock pause per step, to make the job slow in tests",
       0.0,
       1e6,
       false,
       {},
       false},
  };
  c.run = run_checkpoint_demo;
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_checkpoint_demo_case()); // core/registry.hpp
} // namespace

} // namespace sph
