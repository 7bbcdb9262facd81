#include "core/rover_model.hpp"

#include "core/friction_synthesis.hpp"

namespace rover {

RoverModel make_rover_model(RoverParameters parameters, Terrain terrain) {
  parameters.friction.gammas = friction_gammas_for(parameters.friction);
  RoverModel model{parameters, build_kinematic_tree(parameters), std::move(terrain)};
  return model;
}

}  // namespace rover
