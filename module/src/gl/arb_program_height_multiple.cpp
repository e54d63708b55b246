// The height program's light scattered more than once (see the header).
#include "arb_program_height_multiple.hpp"

#include <string>

#include "../core/height_multiple_scattering.hpp"
#include "aerial/phase.hpp"

namespace aerial::detail::arb {

namespace {

/// out = the bilinear interpolation of `array` around a0.x: entries +0 and +1 by t_column, the
/// same on the row +stride, then between the rows by t_row (10 instructions; scratch_a and
/// scratch_b are overwritten).
void write_array_bilinear(ProgramWriter& w, const std::string& array, int stride,
                          const std::string& t_column, const std::string& t_row,
                          const std::string& out, const std::string& scratch_a,
                          const std::string& scratch_b) {
    const auto entry = [&](int offset) {
        return array + (offset == 0 ? "[a0.x]" : "[a0.x + " + std::to_string(offset) + "]");
    };
    const auto lerp = [&](int offset, const std::string& to) {
        w.line("MOV " + scratch_a + ", " + entry(offset) + ";");
        w.line("MOV " + to + ", " + entry(offset + 1) + ";");
        w.line("SUB " + to + ", " + to + ", " + scratch_a + ";");
        w.line("MAD " + to + ", " + to + ", " + t_column + ", " + scratch_a + ";");
    };
    lerp(0, out);
    lerp(stride, scratch_b);
    w.line("SUB " + scratch_b + ", " + scratch_b + ", " + out + ";");
    w.line("MAD " + out + ", " + scratch_b + ", " + t_row + ", " + out + ";");
}

}  // namespace

void write_multiple_scattering_declarations(ProgramWriter& w) {
    using S = MultipleScatteringSlice;
    w.line("PARAM msk = " + format_float4(1.0, -1.0, 0.5, 1e-6) + ";",
           "1, -1, 1/2, the smallest sine product of an azimuth");
    w.line("PARAM msl = " +
               format_float4(S::kViewRows - 2, S::kAzimuthRows - 2, S::kAzimuthRows, 1e-30) + ";",
           "last view and azimuth cells, azimuth rows, tiny");
    w.line("PARAM msh = " +
               format_float4(S::kAltitudeRows - 1, S::kAltitudeRows - 2, 0.0, S::kAltitudeRows) +
               ";",
           "last altitude row and cell, 0, altitude rows");
    w.line("PARAM msu = " +
               format_float4(S::kMaxSunZenithRad, (S::kSunRows - 1) / S::kMaxSunZenithRad,
                             S::kSunRows - 1, S::kSunRows - 2) +
               ";",
           "level's last sun zenith angle, rows per radian, last sun row and cell");
    // acos(x) ~ sqrt(1 - x) (a0 + a1 x + a2 x^2 + a3 x^3) on [0, 1], within 6.7e-5 rad
    // (Abramowitz and Stegun 4.4.45), and pi - acos(-x) below 0.
    w.line("PARAM acs = " + format_float4(1.5707288, -0.2121144, 0.0742610, -0.0187293) + ";",
           "acos's polynomial");
    w.line("PARAM acp = " + format_float4(kPi, -2.0, 0.0, 0.0) + ";");
    w.line("PARAM msy = " +
               format_float4(S::kShapeAltitudeRows - 1, S::kShapeAltitudeRows - 2, S::kShapeRows,
                             0.0) +
               ";",
           "last shape altitude row and cell, rows per altitude row");
    w.line("ADDRESS a0;");
    w.line("TEMP msv, mssr, mssm, msa, msb, msc, msd, mse, msf, mst, msw;");
}

void write_multiple_scattering_view_cell(ProgramWriter& w) {
    w.comment("Higher orders: the view's cell in (view cosine, sin(azimuth/2)) -> msv.");
    w.line("DP3 msa.x, seg, msz;");
    w.line("DP3 msa.y, seg, sunc;");
    w.line("MUL msa.xy, msa, node.w;", "mu_v, cos theta");
    w.line("MIN msa.x, msa.x, msk.x;");
    w.line("MAX msa.x, msa.x, msk.y;");
    w.line("MAD msa.z, -msa.x, msa.x, msk.x;", "1 - mu_v^2");
    w.line("MAX msa.z, msa.z, msl.w;");
    w.line("RSQ msa.w, msa.z;");
    w.line("MUL msa.z, msa.z, msa.w;");
    w.line("MUL msa.z, msa.z, mss.x;", "sin(view zenith) sin(sun zenith)");
    w.line("MAX msa.z, msa.z, msk.w;");
    w.line("RCP msa.z, msa.z;");
    w.line("MAD msa.y, -msa.x, msz.w, msa.y;");
    w.line("MUL msa.y, msa.y, msa.z;", "cos(azimuth from the sun)");
    w.line("MIN msa.y, msa.y, msk.x;");
    w.line("MAX msa.y, msa.y, msk.y;");
    w.line("MAD msa.y, msa.y, -msk.z, msk.z;");
    w.line("MAX msa.y, msa.y, msl.w;");
    w.line("RSQ msa.z, msa.y;");
    w.line("MUL msa.y, msa.y, msa.z;", "sin(azimuth/2)");
    w.line("MAD msa.x, msa.x, mss.y, mss.y;", "view row coordinate");
    w.line("MUL msa.y, msa.y, mss.z;", "azimuth row coordinate");
    w.line("FLR msb.xy, msa;");
    w.line("MIN msb.xy, msb, msl;");
    w.line("SUB msv.yz, msa.xxyw, msb.xxyw;", "fractions");
    w.line("MAD msv.x, msb.x, msl.z, msb.y;", "first cell's row");
}

void write_multiple_scattering_shape(ProgramWriter& w) {
    using S = MultipleScatteringSlice;
    w.comment("Higher orders: shape(h, v) at their mean altitude -> msv.");
    w.line("MAX msa.x, msw.x, msl.w;");
    w.line("RCP msa.x, msa.x;");
    w.line("MUL msa.x, msw.y, msa.x;", "the higher orders' mean altitude");
    w.line("MAX msa.x, msa.x, msh.z;");
    w.line("MAD msa.x, msa.x, msq.x, msk.x;", "1 + h / knee");
    w.line("LG2 msa.x, msa.x;");
    w.line("MUL msa.x, msa.x, msq.y;", "altitude row coordinate");
    w.line("MIN msa.x, msa.x, msy.x;");
    w.line("FLR msa.y, msa.x;");
    w.line("MIN msa.y, msa.y, msy.y;");
    w.line("SUB msa.x, msa.x, msa.y;", "fraction");
    w.line("MAD msa.y, msa.y, msy.z, msv.x;", "first cell's row");
    for (int layer = 0; layer < 2; ++layer) {
        if (layer == 1) w.line("ADD msa.y, msa.y, msy.z;", "the altitude row above");
        w.line("ARL a0.x, msa.y;");
        write_array_bilinear(w, "shp", S::kAzimuthRows, "msv.z", "msv.y",
                             layer == 0 ? "msd" : "mse", "msb", "msc");
    }
    w.line("SUB msv, mse, msd;");
    w.line("MAD msv, msv, msa.x, msd;", "shape(h, v)");
}

void write_multiple_scattering_levels(ProgramWriter& w) {
    w.comment("Higher orders: level(h_n, mu_n) times the weights, summed (mssr: R, mssm: M).");
    w.line("MAX msa.xyz, colm, msh.z;");
    w.line("MAD msb.xyz, planet.y, num.x, msa;", "2 R + h");
    w.line("MUL msa.xyz, msa, msb;");
    w.line("MAX msa.xyz, msa, msl.w;");
    w.line("RSQ msb.x, msa.x;");
    w.line("RSQ msb.y, msa.y;");
    w.line("RSQ msb.z, msa.z;");
    w.line("MUL msa.xyz, msa, msb;", "sqrt(h (2 R + h))");
    w.line("MUL msa.xyz, msa, mss.w;");
    w.line("MIN msa.xyz, msa, msh.x;", "altitude row coordinates");
    w.line("FLR msb.xyz, msa;");
    w.line("MIN msb.xyz, msb, msh.y;");
    w.line("SUB msa.xyz, msa, msb;", "altitude fractions");
    w.comment("The sun at the points: linear in its cosine between the eye's and the vertex's.");
    w.line("ADD mst.x, msw.z, -msz.w;");
    w.line("MAD mst.xyz, work, mst.x, msz.w;", "mu_s at the points");
    w.line("MAX mse.xyz, mst, -mst;", "|mu_s|");
    w.line("MAD msf.xyz, mse, acs.w, acs.z;");
    w.line("MAD msf.xyz, msf, mse, acs.y;");
    w.line("MAD msf.xyz, msf, mse, acs.x;");
    w.line("ADD mse.xyz, msk.x, -mse;");
    w.line("MAX mse.xyz, mse, msl.w;");
    w.line("RSQ msc.x, mse.x;");
    w.line("RSQ msc.y, mse.y;");
    w.line("RSQ msc.z, mse.z;");
    w.line("MUL mse.xyz, mse, msc;");
    w.line("MUL msf.xyz, msf, mse;", "acos |mu_s|");
    w.line("SLT msc.xyz, mst, msh.z;");
    w.line("MAD mse.xyz, msf, acp.y, acp.x;");
    w.line("MAD msf.xyz, msc, mse, msf;", "the sun's zenith angles");
    w.line("MUL mst.xyz, msf, msu.y;");
    w.line("MAX mst.xyz, mst, msh.z;");
    w.line("MIN mst.xyz, mst, msu.z;", "sun row coordinates");
    w.line("FLR mse.xyz, mst;");
    w.line("MIN mse.xyz, mse, msu.w;");
    w.line("SUB mst.xyz, mst, mse;", "sun fractions");
    w.line("MAD msb.xyz, mse, msh.w, msb;", "first rows");
    for (int n = 0; n < 3; ++n) {
        const std::string lane(1, "xyz"[n]);
        w.line("ARL a0.x, msb." + lane + ";");
        w.comment("level at point " + std::to_string(n));
        write_array_bilinear(w, "lev", MultipleScatteringSlice::kAltitudeRows, "msa." + lane,
                             "mst." + lane, "msc", "mse", "msf");
        w.line("MUL mse.xyz, extr, rho." + lane + ";");
        w.line("MAD mse.xyz, extm, sphi." + lane + ", mse;", "-tau_c log2(e)");
        w.line("EX2 mse.x, mse.x;");
        w.line("EX2 mse.y, mse.y;");
        w.line("EX2 mse.z, mse.z;");
        w.line("MUL msc.xyz, msc, mse;", "times each channel's own attenuation");
        w.line("MUL mse.w, seg." + lane + ", msr.y;");
        w.line("MAD mse.w, alt." + lane + ", msm.y, mse.w;");
        w.line("MUL mse.w, mse.w, msc.y;", "the point's share of them (G)");
        if (n == 0) {
            w.line("MUL mssr, msc, seg.x;");
            w.line("MUL mssm, msc, alt.x;");
            w.line("MOV msw.x, mse.w;");
            w.line("MUL msw.y, mse.w, colm.x;");
        } else {
            w.line("MAD mssr, msc, seg." + lane + ", mssr;");
            w.line("MAD mssm, msc, alt." + lane + ", mssm;");
            w.line("ADD msw.x, msw.x, mse.w;");
            w.line("MAD msw.y, mse.w, colm." + lane + ", msw.y;", "shares, shares x altitudes");
        }
    }
}

}  // namespace aerial::detail::arb
