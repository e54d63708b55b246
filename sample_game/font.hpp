// sample_game/font.hpp — a 5×7 bitmap font drawn as GL quads, for the on-screen readout.
//
// How to use this:
//   1. After the frame, `draw_text(api, width, height, x, y, scale, "FPS 60")` draws upper-case
//      letters, digits and . : - / % = + ( ) with the top-left corner at pixel (x, y) (y down),
//      each glyph cell 6 × 8 pixels times `scale`, white on a dark box for legibility.
//   2. It sets its own projection and modelview (an orthographic pixel grid) and puts them back.
#pragma once

#include <string_view>

#include "aerial/gl_api.hpp"

namespace sample {

/// Width in pixels of `text` at `scale`.
int text_width(std::string_view text, int scale);

void draw_text(const aerial::gl::Api& api, int viewport_width, int viewport_height, int x, int y,
               int scale, std::string_view text);

}  // namespace sample
