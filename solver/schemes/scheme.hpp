// The interface every time-integration scheme offers the shared time loop (cases/time_loop.hpp),
// and its registry entry.
//
// A scheme family (isph, wcsph_tvf, ...) keeps its numerics in a class template on dimension,
// kernel and its variants (the policy types chosen once per job, so that pair loops carry no
// option branches); FlowScheme<D> is the boundary the time loop and the cases see, one virtual call
// per step. Its registry entry (SchemeInfo) states the scheme's parameters once (a ParamTable)
// and creates the scheme for a flow from a job's parameters:
//
//   case  --Flow<D>-->  SchemeInfo::make<D>(params, flow)  -->  FlowScheme<D>
//   time loop: while (!s.finished(t, t_end)) { case hooks; s.advance(t, t_end); probes; ... }
//
// A scheme sees the particles through Flow: fluid particles are integrated; Wall and Body
// particles are solid (not integrated; their prescribed velocity, when the case gives one, is the
// vector field flow.v_wall). A solid scheme (schemes/solid/) integrates Solid particles and holds
// its Wall particles fixed (a clamp). Adding a scheme: one folder schemes/<name>/ whose .cpp
// registers a SchemeInfo beside its class (core/registry.hpp).
#pragma once

#include "core/domain.hpp"
#include "core/neighbor_list.hpp"
#include "core/params.hpp"
#include "core/particles.hpp"
#include "core/registry.hpp"
#include "core/run.hpp"

#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph {

// Named arrays of doubles: a checkpoint's content (io/checkpoint.hpp), key -> array.
using StateArrays = std::map<std::string, std::vector<double>>;

// What a case hands a scheme: the particles and the flow's reference scales.
template <int D>
struct Flow {
  Particles<D>* p = nullptr;
  Domain<D> box;     // periodic axes; a non-periodic box is not a bound (the cells follow)
  double rho0 = 1.0; // reference density
  double U = 1.0;    // reference speed (sound speed, time-step criteria)
  double L = 1.0;    // reference length (nu = U L / Re)
  double Re = 100.0; // Reynolds number U L / nu
  double dx = 0.01;  // initial particle spacing
  double dt = 0.0;   // a fixed time step the case asks for (schemes with fixed steps: isph)
  int v_wall = -1;   // vector field: prescribed velocity of the solid particles (-1: at rest)
  int h = -1;        // scalar field: per-particle smoothing length, variable resolution (-1: one
                     // h from the scheme's h_over_dx dx); a scheme without it rejects the flow
  std::vector<SlipWall> slip_walls; // planes with a slip condition (a scheme that has no slip
                                    // walls, SchemeInfo::slip_walls false, rejects the flow)
  int normal = -1; // vector field: outward unit normal of the Body particles (-1: none; a scheme
                   // with a body-pressure condition needs it)
  bool normals_follow_bodies = false; // body_motion also turns `normal` with the moving bodies
  // Open boundaries: sets the pressure of the Buffer particles on the current neighbour list,
  // called by a scheme whenever it updates pressures (empty: buffers keep theirs).
  std::function<void(Particles<D>&, const NeighborList<D>&)> buffer_pressure;
  // Elastic material of the Solid particles (solid schemes, schemes/solid/): Young's modulus and
  // Poisson ratio (in 2D the 3D Lame constants: a plane-strain slab).
  double youngs_modulus = 0.0;
  double poisson_ratio = 0.0;
  // Solid schemes: vector field of an external force on each Solid particle (N; e.g. the fluid's
  // force on a coupled solid, coupling/fsi.hpp), added to its acceleration as f / m (-1: none).
  int external_force = -1;
  // Moving bodies coupled to a solid (fluid schemes with SchemeInfo::moving_bodies; coupling/
  // fsi.hpp; a scheme without them rejects a flow that sets any):
  //   a_wall       vector field: acceleration of the wall particles (wall pressure extrapolation)
  //   wall_force   vector field the scheme fills: the fluid's force on each wall particle, the
  //                reaction of the pair terms the fluid felt, averaged over the last step
  //   body_motion  called after each step's sub-steps, before the neighbour search, with the
  //                step's start time and size: moves the wall particles (advances the solid)
  int a_wall = -1;
  int wall_force = -1;
  std::function<void(Particles<D>&, double t0, double Dt)> body_motion;
  bool has_moving_body_hooks() const { return a_wall >= 0 || wall_force >= 0 || body_motion; }
  // Free-surface / free-stream boundary pieces (boundaries/open_boundary.hpp) a scheme calls
  // inside its step; a scheme without them (SchemeInfo::free_stream false) rejects a flow that
  // sets any. Empty: none.
  //   before_density(p, list)  before the density reinitialisation, on the step's neighbour list
  //                            (e.g. the surface indicator from the position divergence)
  //   after_density(p, list)   after it (e.g. the near-surface density rule)
  //   after_kick(p, t)         after every velocity update, at the sub-step's time t (e.g. the
  //                            free-stream velocity correction of surface particles)
  //   surface_indicator        scalar field, nonzero on free-surface particles: a scheme's
  //                            particle-shifting (transport-velocity) correction skips them
  //                            (SPHinXsys' TransportVelocityCorrection<BulkParticles>); -1: none
  std::function<void(Particles<D>&, const NeighborList<D>&)> before_density, after_density;
  std::function<void(Particles<D>&, double)> after_kick;
  int surface_indicator = -1;
  bool has_free_stream_hooks() const {
    return before_density || after_density || after_kick || surface_indicator >= 0;
  }
  double nu() const { return U * L / Re; }
};

// What one step did.
struct StepStats {
  double dt = 0.0;     // the step taken
  int substeps = 0;    // acoustic sub-steps (wcsph), inner iterations (alsph), ...
  double v_max = 0.0;  // largest fluid speed at the start of the step (0: not measured)
  double tv_max = 0.0; // transport-velocity magnitude of the step (wcsph_tvf), else 0
};

template <int D>
class FlowScheme {
public:
  virtual ~FlowScheme() = default;

  // Set-up on the flow's particles (neighbour search, reference density): once, before the
  // first step, on the initial configuration.
  virtual void init() = 0;
  // After the particles were restored from a checkpoint (and load_state): whatever must be
  // rebuilt on the restored positions.
  virtual void resume() {}

  // One step from t towards t_end; advances t. Throws std::runtime_error when the step cannot be
  // made (a failed linear solve): the time loop records the job as diverged.
  virtual StepStats advance(double& t, double t_end) = 0;
  // True when the scheme's steps have reached t_end.
  virtual bool finished(double t, double t_end) const { return t >= t_end * (1.0 - 1e-12); }
  // The stable step the scheme would take now.
  virtual double stable_dt() const = 0;
  // Ask for (or not) the scheme's costly diagnostics in the next step (ISPH: the divergence of
  // the new velocity); a scheme without such diagnostics ignores it.
  virtual void measure_next_step(bool) {}

  // Prescribed velocities of the solid particles replaced by what the fluid sees at the wall
  // (the no-slip mirror velocity), for profiles and fields drawn to the wall.
  virtual void wall_velocities_for_output() = 0;
  // Neighbour list of the current positions (between steps).
  virtual const NeighborList<D>& neighbors() const = 0;
  // The kernel's name and smoothing length (for diagnostics that interpolate with it).
  virtual const std::string& kernel_name() const = 0;
  virtual double h() const = 0;
  // The force of the fluid on the solid particles; `viscous`: its viscous part.
  virtual Vec<D> force_on_walls(Vec<D>* viscous = nullptr) {
    (void)viscous;
    throw std::logic_error("this scheme does not compute wall forces");
  }

  // A uniform body acceleration g (gravity, the driving of a smooth start) on the fluid from the
  // next step on (zero until set); a scheme without body forces throws.
  virtual void set_body_acceleration(const Vec<D>& g) {
    (void)g;
    throw std::logic_error("this scheme does not take a body acceleration");
  }

  // The case added, removed or re-kinded particles between steps (open boundaries): rebuild what
  // depends on the particle set (neighbour lists). A scheme that searches every step ignores it.
  virtual void particles_changed() {}

  // Named state carried from one step to the next besides the particle fields (checkpoints).
  virtual std::vector<std::string> state_names() const = 0;
  virtual void save_state(StateArrays& out) const = 0;
  virtual void load_state(const StateArrays& in) = 0;

  // Named diagnostics of the last step for a case's series (ISPH: div_max, ppe_iters).
  virtual std::vector<std::pair<std::string, double>> probes() const { return {}; }

  // The scheme's own metrics (counters, solver statistics, cost), added at the end of a run.
  virtual void add_metrics(RunResult& res, double wall_s) const = 0;
  // Elementary steps for the cost per particle-step (acoustic sub-steps, or steps).
  virtual long work_steps() const = 0;
  // Elementary steps the next step would take (wcsph_tvf: its acoustic sub-steps), for the cost
  // estimate of a job before it runs.
  virtual double work_per_step() const { return 1.0; }
  // A solid scheme's deformation gradient F of each particle at the current positions (in the
  // particle order; coupling/fsi.hpp turns the wall normals with it); nullptr: not a solid.
  virtual const std::vector<Mat<D>>* deformation_gradient() const { return nullptr; }
};

// A scheme's registry entry: its parameters and how it is made for a 2D or 3D flow.
// A recorded metric or an HDF5 dataset, with its one-line meaning (runner cases CASE).
struct OutputDoc {
  std::string name;
  std::string doc;
};

struct SchemeInfo {
  std::string name;
  std::string description; // one line, with the paper
  std::vector<ParamSpec> params;
  // The scheme's own counters among a job's metrics (add_metrics), name and one-line meaning.
  std::vector<OutputDoc> metrics;
  bool slip_walls = false;    // imposes Flow::slip_walls
  bool free_stream = false;   // calls Flow's before_density, after_density, after_kick hooks
  bool moving_bodies = false; // takes Flow's a_wall, wall_force and body_motion
  std::unique_ptr<FlowScheme<2>> (*make2)(const Params&, const Flow<2>&) = nullptr;
  std::unique_ptr<FlowScheme<3>> (*make3)(const Params&, const Flow<3>&) = nullptr;
};

// All registered schemes (by name), and look-up by name (nullptr if unknown).
inline const std::vector<SchemeInfo>& scheme_registry() {
  return Registry<SchemeInfo>::entries();
}
inline const SchemeInfo* find_scheme(const std::string& name) {
  return Registry<SchemeInfo>::find(name);
}

// The scheme a job names (parameter "scheme"; `fallback` when it names none), made for flow.
template <int D>
std::unique_ptr<FlowScheme<D>> make_scheme(const Params& prm, const Flow<D>& flow,
                                           const std::string& fallback) {
  const std::string name = prm.count("scheme") ? get_string(prm, "scheme") : fallback;
  const SchemeInfo* s = find_scheme(name);
  if (!s)
    throw std::invalid_argument("unknown scheme '" + name + "'");
  auto make = [&] {
    if constexpr (D == 2)
      return s->make2;
    else
      return s->make3;
  }();
  if (!make)
    throw std::invalid_argument("scheme '" + name + "' does not run in " + std::to_string(D) + "D");
  if (!flow.slip_walls.empty() && !s->slip_walls)
    throw std::invalid_argument("scheme '" + name + "' has no slip walls, which this case needs");
  if (flow.has_free_stream_hooks() && !s->free_stream)
    throw std::invalid_argument("scheme '" + name +
                                "' has no free-stream boundary hooks, which this case needs");
  if (flow.has_moving_body_hooks() && !s->moving_bodies)
    throw std::invalid_argument("scheme '" + name +
                                "' has no moving-body coupling, which this case needs");
  return make(prm, flow);
}

} // namespace sph
