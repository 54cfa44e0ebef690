// Fluid-structure coupling of an elastic solid (schemes/solid/, its own particle set and scheme)
// with a fluid scheme that has moving bodies (SchemeInfo::moving_bodies: wcsph_tvf), as Zhang,
// Rezavand & Hu, "A multi-resolution SPH method for fluid-structure interactions", J. Comput.
// Phys. 429 (2021) 110028 (seed 002 ref. [38]), section 3, and SPHinXsys (github.com/Xiangyu-Hu/
// SPHinXsys: solid_dynamics/fluid_structure_interaction.{h,hpp}, AverageVelocityAndAcceleration;
// the FSI2 example test_2d_fsi2), read for the formulas, written anew.
//
// What it does:
//   images     every particle of the solid set (Solid and its clamp's Wall particles) has an image
//              in the fluid set: a Wall particle of the fluid's spacing (m = rho_f dx^D, rho_f),
//              tagged with the solid particle's id plus one (scalar field "fsi/solid_id"; 0 on
//              every other particle, also those added later: new particles get 0); the fluid sees
//              the solid as moving wall particles (no-slip by 2 v_w - v_i, wall pressure
//              extrapolated with the relative acceleration).
//   force      the fluid scheme fills the field wall_force with the force of the fluid on each
//              image, the reaction of the pair terms the fluid felt from it over the step
//              (pressure, viscous, Riemann dissipation; schemes/wcsph_tvf: ops::Wall*Reaction), so
//              the momentum the two exchange is equal and opposite; it is copied to the solid's
//              external force field (Flow::external_force), f_i = F_image(i).
//   sub-steps  after each fluid step [t0, t0 + Dt] (the fluid's body_motion hook): the solid takes
//              its own acoustic steps (dt_s = cfl h / (c_p + |v|max), several per fluid step, the
//              last one shortened to land on t0 + Dt) with the fluid force held fixed;
//   averages   the fluid sees the solid's velocity and acceleration averaged over the sub-steps
//              (Zhang et al. 2021; SPHinXsys' AverageVelocityAndAcceleration):
//                v_ave_i = (x_i(t0 + Dt) - x_i(t0)) / Dt,  a_ave_i = (v_ave_i - v_ave_i,prev) / Dt
//              and the images are moved to the solid's positions (before the fluid's neighbour
//              search).
//   normals    optional (follow_normals): the images' wall normals turn with the solid, as
//              SPHinXsys' solid normal update (the normal of a surface element under F):
//                n_i = F_i^-T n0_i / |F_i^-T n0_i|
//              with n0_i the image's normal in the reference configuration and F_i the solid
//              scheme's deformation gradient at the step's end positions.
// The coupling is explicit and staggered: the fluid step sees the solid's positions and averaged
// velocity of the end of the previous step, the solid step the fluid's force of the step just
// made (SPHinXsys exchanges at every acoustic sub-step of the fluid; here at the advection step:
// docs/fsi.md).
#pragma once

#include "core/particles.hpp"
#include "schemes/scheme.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace sph::fsi {

template <int D>
class SolidFluidCoupling {
public:
  // Adds the solid's fields (external force, averaged velocity) to the solid set, and to the
  // fluid set the images of every solid particle (see the header) with the fields the fluid
  // scheme needs (v_wall, a_wall, wall_force, fsi/solid_id). Call once while building, before
  // either scheme exists. v_wall: the fluid set's prescribed-velocity field if it has one (-1:
  // added here).
  void add_images(Particles<D>& fluid, Particles<D>& solid, double rho_f, double dx,
                  int v_wall = -1) {
    f_ext_ = solid.add_vector("fsi/force_from_fluid");
    v_ave_ = solid.add_vector("fsi/v_ave");
    id_ = fluid.add_scalar("fsi/solid_id", 0.0);
    v_wall_ = v_wall >= 0 ? v_wall : fluid.add_vector("v_wall");
    a_wall_ = fluid.add_vector("a_wall");
    wall_force_ = fluid.add_vector("wall_force");
    const double m = rho_f * std::pow(dx, D);
    for (std::size_t i = 0; i < solid.size(); ++i) {
      const std::size_t k = fluid.add(solid.r[i], m, rho_f, Kind::Wall);
      fluid.scalar(id_)[k] = static_cast<double>(solid.id[i] + 1);
    }
    fluid_ = &fluid, solid_ = &solid;
  }

  // The images' wall normals (the fluid flow's `normal` field, set by the case in the reference
  // configuration) turn with the solid at every step (see the header). Call after add_images;
  // start() keeps the images' normals as n0 in the solid set (field fsi/normal0, so checkpoints
  // carry it).
  void follow_normals(Flow<D>& fluid_flow) {
    if (fluid_flow.normal < 0 || !solid_)
      throw std::logic_error("fsi: follow_normals needs the images and the fluid's normals");
    normal_ = fluid_flow.normal;
    normal0_ = solid_->add_vector("fsi/normal0");
    fluid_flow.normals_follow_bodies = true;
  }

  // The fields and hook of the two flows.
  void attach(Flow<D>& fluid_flow, Flow<D>& solid_flow) {
    fluid_flow.v_wall = v_wall_;
    fluid_flow.a_wall = a_wall_;
    fluid_flow.wall_force = wall_force_;
    fluid_flow.body_motion = [this](Particles<D>& p, double t0, double Dt) { step(p, t0, Dt); };
    solid_flow.external_force = f_ext_;
  }

  // After both schemes' init() (or resume()): the solid scheme to advance and the map from the
  // solid's ids to its (sorted, then fixed) particle order.
  void start(FlowScheme<D>& solid_scheme) {
    scheme_ = &solid_scheme;
    index_.assign(solid_->size(), -1);
    for (std::size_t i = 0; i < solid_->size(); ++i) {
      const auto id = solid_->id[i];
      if (id < 0 || static_cast<std::size_t>(id) >= index_.size())
        throw std::logic_error("fsi: solid particle ids must be 0..N-1");
      index_[static_cast<std::size_t>(id)] = static_cast<long>(i);
    }
    if (normal_ >= 0) { // n0: the images' normals as the case set them (the first step turns them)
      auto& n0 = solid_->vector(normal0_);
      const auto& n = fluid_->vector(normal_);
      for (std::size_t k = 0; k < fluid_->size(); ++k)
        if (const long i = solid_index(*fluid_, k); i >= 0)
          n0[static_cast<std::size_t>(i)] = n[k];
    }
  }

  int images_solid_id_field() const { return id_; }
  int wall_force_field() const { return wall_force_; }
  int external_force_field() const { return f_ext_; }
  // Solid steps taken by the last fluid step, and in all.
  int last_substeps() const { return last_substeps_; }
  long substeps() const { return substeps_; }
  void set_substeps(long n) { substeps_ = n; }

  // Index in the solid set of fluid particle k's solid particle (-1: k is not an image).
  long solid_index(const Particles<D>& fluid, std::size_t k) const {
    const double id = fluid.scalar(id_)[k];
    return id < 0.5 ? -1 : index_[static_cast<std::size_t>(id) - 1];
  }

  // The fluid's body_motion hook (see the header): force to the solid, sub-steps over [t0, t0 +
  // Dt], averaged velocity and acceleration, images moved.
  void step(Particles<D>& fluid, double t0, double Dt) {
    Particles<D>& s = *solid_;
    auto& f = s.vector(f_ext_);
    const auto& fw = fluid.vector(wall_force_);
    for (std::size_t k = 0; k < fluid.size(); ++k) {
      const long i = solid_index(fluid, k);
      if (i >= 0)
        f[static_cast<std::size_t>(i)] = fw[k];
    }
    x0_ = s.r;
    double t = t0;
    const double t1 = t0 + Dt;
    last_substeps_ = 0;
    while (!scheme_->finished(t, t1)) {
      scheme_->advance(t, t1);
      ++last_substeps_;
    }
    substeps_ += last_substeps_;
    auto& v_ave = s.vector(v_ave_);
    a_ave_.resize(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Vec<D> v = (s.r[i] - x0_[i]) / Dt;
      a_ave_[i] = (v - v_ave[i]) / Dt;
      v_ave[i] = v;
    }
    auto& vw = fluid.vector(v_wall_);
    auto& aw = fluid.vector(a_wall_);
    // Turned normals (follow_normals): n_k = F_i^-T n0_i / |F_i^-T n0_i|.
    const std::vector<Mat<D>>* F = normal_ >= 0 ? scheme_->deformation_gradient() : nullptr;
    if (normal_ >= 0 && !F)
      throw std::logic_error("fsi: the solid scheme has no deformation gradient");
    auto* n = F ? &fluid.vector(normal_) : nullptr;
    const auto* n0 = F ? &s.vector(normal0_) : nullptr;
    for (std::size_t k = 0; k < fluid.size(); ++k) {
      const long i = solid_index(fluid, k);
      if (i < 0)
        continue;
      const auto u = static_cast<std::size_t>(i);
      fluid.r[k] = s.r[u];
      fluid.v[k] = vw[k] = v_ave[u];
      aw[k] = a_ave_[u];
      if (F)
        (*n)[k] = ((*F)[u].inverse().transpose() * (*n0)[u]).normalized();
    }
  }

private:
  Particles<D>* fluid_ = nullptr;
  Particles<D>* solid_ = nullptr;
  FlowScheme<D>* scheme_ = nullptr;
  int f_ext_ = -1, v_ave_ = -1, id_ = -1, v_wall_ = -1, a_wall_ = -1, wall_force_ = -1;
  int normal_ = -1, normal0_ = -1;
  std::vector<long> index_;
  std::vector<Vec<D>> x0_, a_ave_;
  int last_substeps_ = 0;
  long substeps_ = 0;
};

} // namespace sph::fsi
