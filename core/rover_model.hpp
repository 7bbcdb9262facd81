// The SA model as data: parameters, the kinematic tree built from them, and the
// terrain. Immutable once made, so one RoverModel can be shared by any number
// of threads evaluating the equations of motion at once.
#pragma once

#include "core/kinematic_tree.hpp"
#include "core/rover_parameters.hpp"
#include "core/terrain.hpp"

namespace rover {

struct RoverModel {
  RoverParameters parameters;   // friction gammas resolved (pinned or synthesised)
  KinematicTree tree;
  Terrain terrain = Terrain::flat();
};

// Builds the tree and resolves the friction gammas: the configured set if it
// meets the fit quality bar for mu_s, v_s, mu_k, v_k, otherwise a synthesis
// (docs/model.md §6, "Friction synthesis").
RoverModel make_rover_model(RoverParameters parameters, Terrain terrain = Terrain::flat());

}  // namespace rover
