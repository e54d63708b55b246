// Internal: the height program's light scattered more than once (the `multiple_scattering`
// level; core/height_multiple_scattering.hpp): its declarations and the three pieces the program
// text places among the others (arb_program_height.cpp).
#pragma once

#include "arb_program_internal.hpp"

namespace aerial::detail::arb {

/// The constants, the address register and the temporaries of the higher orders.
void write_multiple_scattering_declarations(ProgramWriter& w);

/// The view's cell of the shape's table into msv (x: its first row within an altitude row, yz:
/// the fractions over the view cosine and sin(azimuth/2)), while seg holds d and node.w 1/s.
void write_multiple_scattering_view_cell(ProgramWriter& w);

/// shape(h, v) into msv: bilinear in the view's cell (msv) on the two altitude rows around the
/// altitude the higher orders come from (msw.y / msw.x), then linear between them.
void write_multiple_scattering_shape(ProgramWriter& w);

/// level(h_n, mu_s,n) at the three points (colm.xyz = h_n, work.xyz = u_n, msw.z the sun's cosine
/// at the vertex), times each channel's attenuation to them (rho, sphi), summed with the weights
/// before the planet's shadow (seg.xyz, alt.xyz: the shadow is in msd.xyz) into mssr (Rayleigh)
/// and mssm (Mie); msw.xy the G channel's shares and shares times altitudes.
void write_multiple_scattering_levels(ProgramWriter& w);

}  // namespace aerial::detail::arb
