// The one time loop of the solver, and the shape of a case that uses it (FlowCase).
//
//   case (geometry, boundary hooks, probes, metrics)
//     -> run_flow_case: builds the particles, makes the job's scheme (schemes/scheme.hpp),
//        then  while (!scheme.finished(t, t_end)):
//                cancelled?  -> save a checkpoint, return Cancelled
//                case.before_step        (boundary hooks: inflow/outflow, ghosts, sponges, ...)
//                scheme.advance(t, t_end)  (a failed step -> Diverged)
//                speed bound              (a fluid or solid speed not finite or above
//                                          case.speed_bound() -> Diverged)
//                case.after_step         (probes, series, steady state -> may end the run)
//                checkpoint when due (every N steps / M s), progress
//        case.finish (final metrics and outputs), scheme.add_metrics, the loop's cost metrics.
//
// With an output directory the loop writes particle snapshots for ParaView (every particle, every
// `output_interval` of simulated time and the final state, also of a diverged run:
// io/particle_snapshot.hpp, parameter in cases/loop_params.hpp). They only read the particles.
//
// Checkpoints are named arrays (key -> array): every particle field ("p/..."), the loop's state
// ("loop/costs"), the case's (case.state_names()) and the scheme's (scheme.state_names()). A
// resumed job rebuilds the initial configuration (so reference densities are the same), restores
// the particles and the named state, and continues bit for bit.
//
// Cost metrics of every run that finished or diverged: steps, wall_time_s, cpu_time_s (process CPU
// time of the loop, summed over the resumes of a checkpointed job), time_per_step_s (wall
// per step), cpu_time_per_step_s (process CPU time of the loop per step: the honest cost on a
// shared machine), time_per_particle_step_s (wall per particle and elementary step of the scheme:
// acoustic sub-steps of wcsph_tvf, steps of isph), n_particles (the largest particle count of the
// run, every kind: constant for closed boxes; with inflow, outflow and ghosts, their maximum).
// A diverged run also records t_stop, the case's diverged() metrics and the scheme's.
#pragma once

#include "cases/case.hpp"
#include "cases/loop_params.hpp"
#include "io/checkpoint.hpp"
#include "io/particle_checkpoint.hpp"
#include "io/particle_snapshot.hpp"
#include "schemes/scheme.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <omp.h>
#include <stdexcept>
#include <string>

namespace sph {

// Where the loop stands, for a case's hooks.
struct LoopState {
  double t = 0.0;
  long steps = 0;
  double t_end = 0.0;
  double wall_s = 0.0; // wall and process CPU time of the run, earlier attempts included (set for
  double cpu_s = 0.0;  // finish and diverged)
};

// A number in a message, with 6 significant digits (%g): a speed of 1e300 is not 301 digits and a
// time of 1e-10 s is not 0.000000.
inline std::string message_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

template <int D>
class FlowCase {
public:
  virtual ~FlowCase() = default;

  // Geometry: fills the empty particle set p and returns the flow's scales and walls (flow.p is
  // set by the loop).
  virtual Flow<D> build(Particles<D>& p) = 0;
  // After the scheme's init() on the initial configuration (initial samples, reference values).
  virtual void start(FlowScheme<D>&) {}
  virtual double t_end() const = 0;
  // Diverged when a fluid or solid speed exceeds this (or is not finite).
  virtual double speed_bound() const = 0;

  // Boundary hooks before each step.
  virtual void before_step(FlowScheme<D>&, const LoopState&) {}
  // Probes after each step; true ends the run (e.g. a steady state). Throws std::runtime_error
  // when the case finds the state broken (a divergence test of its own): the job is diverged.
  virtual bool after_step(FlowScheme<D>&, const LoopState&, const StepStats&) { return false; }
  // Final metrics and outputs (the loop adds the scheme's metrics and the costs after these).
  virtual void finish(FlowScheme<D>&, const LoopState&, RunResult&) = 0;
  // The metrics and outputs of a run that diverged (what is meaningful of a blown-up state: none by
  // default); the loop adds t_stop, the scheme's metrics and the costs.
  virtual void diverged(FlowScheme<D>&, const LoopState&, RunResult&) {}
  // A note for the job's message ("steady at t = ..."), empty for none.
  virtual std::string summary(const LoopState&) const { return {}; }

  // Named state carried between steps (checkpoints).
  virtual std::vector<std::string> state_names() const { return {}; }
  virtual void save_state(StateArrays&) const {}
  virtual void load_state(const StateArrays&) {}
};

// The size of a flow case's job (JobSize, cases/case.hpp) on its initial configuration, with the
// scheme set up on it: the particles, the steps to t_end at the scheme's stable step there (at
// least the scheme's own reference speed) and the elementary steps per step.
template <int D>
JobSize initial_size(const FlowCase<D>& c, const Particles<D>& p, const FlowScheme<D>& s) {
  JobSize z;
  z.dim = D;
  z.particles = static_cast<double>(p.size());
  const double dt = s.stable_dt();
  z.steps = dt > 0 ? std::ceil(c.t_end() / dt * (1.0 - 1e-12)) : 0.0;
  z.work_per_step = s.work_per_step();
  return z;
}

// A job's initial configuration: the case's geometry in p (flow: its scales and walls) and the
// job's scheme set up on it. The one set-up of both running and sizing a job.
template <int D>
std::unique_ptr<FlowScheme<D>> set_up_flow_case(FlowCase<D>& c, Particles<D>& p, Flow<D>& flow,
                                                const Params& prm,
                                                const std::string& default_scheme) {
  flow = c.build(p);
  flow.p = &p;
  std::unique_ptr<FlowScheme<D>> s = make_scheme<D>(prm, flow, default_scheme);
  s->init();
  return s;
}

// The size of a job without running it (CaseInfo::size).
template <int D>
JobSize size_flow_case(FlowCase<D>& c, const Params& prm, const std::string& default_scheme) {
  Particles<D> p;
  Flow<D> flow;
  const auto s = set_up_flow_case(c, p, flow, prm, default_scheme);
  return initial_size(c, p, *s);
}

// Runs a flow case with the job's scheme (parameter "scheme", else the case's default scheme)
// through the shared loop.
template <int D>
RunResult run_flow_case(FlowCase<D>& c, const Params& prm, const RunContext& ctx,
                        const std::string& default_scheme) {
  using clock = std::chrono::steady_clock;
  omp_set_num_threads(std::max(1, ctx.threads));
  const auto t_start = clock::now();

  Particles<D> p;
  Flow<D> flow;
  std::unique_ptr<FlowScheme<D>> s = set_up_flow_case(c, p, flow, prm, default_scheme);
  // What the cost model predicts for this job (its metric predicted_work; the initial
  // configuration, so a resumed attempt computes the same): a later estimate of the same case
  // learns the model's bias for it from the ratio of CPU time to this.
  const JobSize z0 = initial_size(c, p, *s);
  const double predicted_work = z0.particles * z0.steps * z0.work_per_step;
  c.start(*s);

  RunResult res;
  LoopState at;
  at.t_end = c.t_end();
  double cpu_before = 0.0, wall_before = 0.0;   // spent by earlier attempts
  double n_max = static_cast<double>(p.size()); // the largest particle count (all kinds)
  std::string resumed;

  io::Checkpointer ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s,
                      ctx.fingerprint.empty() ? solver_fingerprint() : ctx.fingerprint);
  {
    std::vector<std::string> names = io::particle_array_names(p);
    names.push_back("loop/costs");
    names.push_back("loop/n_particles_max");
    for (auto& n : c.state_names())
      names.push_back(n);
    for (auto& n : s->state_names())
      names.push_back(n);
    if (auto st = ck.load(names)) {
      io::restore_particle_arrays(p, st->arrays);
      const auto& costs = st->arrays.at("loop/costs");
      io::expect_state_size(costs, 2, "checkpoint array loop/costs");
      cpu_before = costs[0], wall_before = costs[1];
      const auto& nm = st->arrays.at("loop/n_particles_max");
      io::expect_state_size(nm, 1, "checkpoint array loop/n_particles_max");
      n_max = nm[0];
      c.load_state(st->arrays);
      s->load_state(st->arrays);
      s->resume();
      at.steps = static_cast<long>(st->step), at.t = st->time;
      resumed = io::resumed_message(at.t, ctx.attempt);
    } else {
      resumed = ck.rejection(); // a checkpoint it could not continue: why it started again
    }
  }
  io::ParticleSnapshots<D> snaps(ctx.output_dir, output_interval(prm), p, flow.h, s->h(), at.t,
                                 at.steps);
  const std::clock_t cpu0 = std::clock();
  auto cpu_so_far = [&] {
    return cpu_before + static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  };
  auto wall_so_far = [&] {
    return wall_before + std::chrono::duration<double>(clock::now() - t_start).count();
  };
  auto save = [&] {
    if (!ck.enabled())
      return;
    io::CheckpointState st{at.steps, at.t, {}};
    io::add_particle_arrays(p, st.arrays);
    st.arrays["loop/costs"] = {cpu_so_far(), wall_so_far()};
    st.arrays["loop/n_particles_max"] = {n_max};
    c.save_state(st.arrays);
    s->save_state(st.arrays);
    ck.save(st);
  };
  // The scheme's metrics and the loop's costs, for a run that finished or diverged.
  auto add_costs = [&] {
    s->add_metrics(res, at.wall_s);
    const double N = n_max, steps = static_cast<double>(at.steps);
    res.add("steps", steps);
    res.add("wall_time_s", at.wall_s);
    res.add("cpu_time_s", at.cpu_s);
    if (at.steps > 0) {
      res.add("time_per_step_s", at.wall_s / steps);
      res.add("cpu_time_per_step_s", at.cpu_s / steps);
    }
    res.add("work_steps", static_cast<double>(s->work_steps()));
    if (s->work_steps() > 0)
      res.add("time_per_particle_step_s", at.wall_s / (N * static_cast<double>(s->work_steps())));
    res.add("n_particles", N);
    res.add("dimension", D);
    res.add("predicted_work", predicted_work);
  };
  auto diverged = [&](const std::string& why) {
    snaps.final_state(at.t, at.steps);
    at.wall_s = wall_so_far(), at.cpu_s = cpu_so_far();
    res.status = RunStatus::Diverged;
    res.add("t_stop", at.t);
    c.diverged(*s, at, res);
    add_costs();
    res.message = why + " at t = " + message_number(at.t);
    if (!resumed.empty())
      res.message += "; " + resumed;
    return res;
  };

  const double bound = c.speed_bound();
  while (!s->finished(at.t, at.t_end)) {
    if (stop_if_cancelled(ctx, at.t, res, save))
      return res;
    c.before_step(*s, at);
    StepStats st;
    try {
      st = s->advance(at.t, at.t_end);
    } catch (const std::runtime_error& e) { // e.g. a failed PPE solve: the state is broken
      return diverged(e.what());
    }
    ++at.steps;
    n_max = std::max(n_max, static_cast<double>(p.size()));
    double vmax = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid || p.kind[i] == Kind::Solid) {
        const double v2 = p.v[i].squaredNorm();
        vmax = std::max(vmax, std::isfinite(v2) ? std::sqrt(v2) : 1e300);
      }
    if (!(vmax <= bound))
      return diverged(vmax >= 1e300 ? std::string("velocity not finite")
                                    : "velocity " + message_number(vmax));
    bool stop = false;
    try {
      stop = c.after_step(*s, at, st);
    } catch (const std::runtime_error& e) { // a broken state the case detects (a force not finite)
      return diverged(e.what());
    }
    snaps.after_step(at.t, at.steps);
    if (stop)
      break;
    if (ck.due(at.steps))
      save();
    ctx.report(at.t / at.t_end);
  }
  snaps.final_state(at.t, at.steps);
  at.wall_s = wall_so_far(), at.cpu_s = cpu_so_far();
  c.finish(*s, at, res);
  add_costs();
  std::string m = c.summary(at);
  if (!resumed.empty())
    m = m.empty() ? resumed : m + "; " + resumed;
  res.message = m;
  ck.discard(); // the results are final
  return res;
}

} // namespace sph
