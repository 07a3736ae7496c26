#pragma once
// The stages of the MUSL step (MPM paper App. A.2), one file each in this folder. A stage is a
// free function of the step's state (mpm/state.hpp); its *_stage() builder names it and
// declares the particle columns and engine resources it reads and writes, from which the
// stage graph orders the step (mpm/stage_graph.hpp). The list itself is src/mpm/step.cpp.

#include "mpm/stage_graph.hpp"

namespace shatter::mpm {

struct State;

// 1. sort particles by grid block (and re-order the columns every few steps); stencils at x^n
template <class Shape>
Stage sort_stage(State& s);
// 1, 3. scatter mass, momentum and internal force to the grid (Eqs. 29, 32, 33)
template <class Shape>
Stage p2g_stage(State& s);
// 1c. self-gravity of the nodes' mass, as a nodal body force (gravity.self; stages/gravity.cpp)
Stage self_gravity_stage(State& s);
// 2, 3, 4. boundary conditions and the momentum update on the grid (Eq. 27)
Stage grid_update_stage(State& s);
// 5a. XPIC(m) or FMPM(k): the extra grid-particle-grid passes of the filter, each pass a
// scatter, its exchange (several ranks) and a nodal update: added to the step's graph in order
template <class Shape>
void add_filter_stages(State& s);
// 5. particle velocity and displacement from the grid
template <class Shape>
Stage g2p_stage(State& s);
// 5b. the kinetic energy the filtered update removed, booked as heat (SolverConfig::filter_heat)
Stage filter_heat_stage(State& s);
// 6. MUSL: updated particle momentum back to the grid (the scatter), then, after its exchange
// (several ranks), the nodal velocity with the boundary conditions
template <class Shape>
Stage remap_stage(State& s);
Stage remap_velocity_stage(State& s);
// 7a, 7b. strain and spin increments, density (Eqs. 21, 23), APIC's C_p; then the
// constitutive update per material group (Eqs. 22, 35; EOS, strength, damage), chunk by chunk
template <class Shape>
Stage constitutive_stage(State& s);
// positions move only after steps 6-7, which need the shape functions at x^n
Stage advance_positions_stage(State& s);
// particles past an outflow face leave the store, their energy booked as outflow
Stage outflow_stage(State& s);
// this rank's energy sums (kinetic, potential, internal)
Stage energy_stage(State& s);
// the clock and this rank's max_p (c_p + |v_p|) for the next time step (Eq. 34)
Stage time_step_stage(State& s);

// Shared by the stages and the exchanges.
// Owner block key per particle (State::owner_keys), from the positions.
template <class Shape>
void compute_keys(State& s);
// The scatter of P2G: with_force, the force-carrying scatter of step 1 (mass, momentum, force);
// without, momentum only (the remap and the filter passes). velocity: scatter m_p w_p with
// these particle velocities instead of v_p (momentum only; XPIC).
template <class Shape>
void p2g(State& s, bool with_force, double* const* velocity = nullptr);
// Throws NumericalError at the first particle with a non-finite checked column; the columns in
// `skip` are not read (the sort stage's retake copy checks those).
void check_finite(const State& s, FieldSet skip = {});
// max_p (c_p + |v_p|) of this rank's particles (Eq. 34).
double fastest_local(const State& s);
// dt = CFL h / max_p (c_p + |v_p|) (Eq. 34), capped at dt_max, over every rank.
double stable_dt(const State& s, double fastest);
// After the step's graph: the sums and the next time step over all ranks.
void finish_step(State& s);

}  // namespace shatter::mpm
