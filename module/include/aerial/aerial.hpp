// aerial/aerial.hpp — the whole C++ API in one include.
//
// How to use this:
//   1. auto atmosphere = aerial::atmosphere_preset("earth");          // atmosphere.hpp
//   2. aerial::View view; view.eye = {0, 0, 100}; view.sun_dir = {0, 0.6, 0.8};
//   3. auto frame = aerial::prepare_frame<float>(*atmosphere, view, aerial::Model::height);
//   4. per vertex: aerial::Scattering<float> s = aerial::scatter(*frame, position);  //
//   scattering.hpp
//      colour = texel * s.extinction + s.in_scattering, then exposure.
#pragma once

#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/cache.hpp"
#include "aerial/error.hpp"
#include "aerial/phase.hpp"
#include "aerial/scattering.hpp"
#include "aerial/sky.hpp"
#include "aerial/sun.hpp"
