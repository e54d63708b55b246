#include "font.hpp"

#include <cctype>
#include <cstdint>

namespace sample {
namespace {

/// One glyph: 7 rows of 5 bits, most significant bit on the left.
struct Glyph {
    char c;
    std::uint8_t rows[7];
};

// clang-format off
constexpr Glyph kGlyphs[] = {
    {'0', {14, 17, 19, 21, 25, 17, 14}}, {'1', {4, 12, 4, 4, 4, 4, 14}},
    {'2', {14, 17, 1, 2, 4, 8, 31}},     {'3', {31, 2, 4, 2, 1, 17, 14}},
    {'4', {2, 6, 10, 18, 31, 2, 2}},     {'5', {31, 16, 30, 1, 1, 17, 14}},
    {'6', {6, 8, 16, 30, 17, 17, 14}},   {'7', {31, 1, 2, 4, 8, 8, 8}},
    {'8', {14, 17, 17, 14, 17, 17, 14}}, {'9', {14, 17, 17, 15, 1, 2, 12}},
    {'A', {14, 17, 17, 31, 17, 17, 17}}, {'B', {30, 17, 17, 30, 17, 17, 30}},
    {'C', {14, 17, 16, 16, 16, 17, 14}}, {'D', {28, 18, 17, 17, 17, 18, 28}},
    {'E', {31, 16, 16, 30, 16, 16, 31}}, {'F', {31, 16, 16, 30, 16, 16, 16}},
    {'G', {14, 17, 16, 23, 17, 17, 15}}, {'H', {17, 17, 17, 31, 17, 17, 17}},
    {'I', {14, 4, 4, 4, 4, 4, 14}},      {'J', {7, 2, 2, 2, 2, 18, 12}},
    {'K', {17, 18, 20, 24, 20, 18, 17}}, {'L', {16, 16, 16, 16, 16, 16, 31}},
    {'M', {17, 27, 21, 21, 17, 17, 17}}, {'N', {17, 17, 25, 21, 19, 17, 17}},
    {'O', {14, 17, 17, 17, 17, 17, 14}}, {'P', {30, 17, 17, 30, 16, 16, 16}},
    {'Q', {14, 17, 17, 17, 21, 18, 13}}, {'R', {30, 17, 17, 30, 20, 18, 17}},
    {'S', {15, 16, 16, 14, 1, 1, 30}},   {'T', {31, 4, 4, 4, 4, 4, 4}},
    {'U', {17, 17, 17, 17, 17, 17, 14}}, {'V', {17, 17, 17, 17, 17, 10, 4}},
    {'W', {17, 17, 17, 21, 21, 21, 10}}, {'X', {17, 17, 10, 4, 10, 17, 17}},
    {'Y', {17, 17, 17, 10, 4, 4, 4}},    {'Z', {31, 1, 2, 4, 8, 16, 31}},
    {'.', {0, 0, 0, 0, 0, 12, 12}},      {':', {0, 12, 12, 0, 12, 12, 0}},
    {'-', {0, 0, 0, 31, 0, 0, 0}},       {'/', {0, 1, 2, 4, 8, 16, 0}},
    {'%', {24, 25, 2, 4, 8, 19, 3}},     {'=', {0, 0, 31, 0, 31, 0, 0}},
    {'+', {0, 4, 4, 31, 4, 4, 0}},       {'(', {2, 4, 8, 8, 8, 4, 2}},
    {')', {8, 4, 2, 2, 2, 4, 8}},
};
// clang-format on

const Glyph* find_glyph(char c) {
    const char upper = char(std::toupper(static_cast<unsigned char>(c)));
    for (const Glyph& g : kGlyphs) {
        if (g.c == upper) return &g;
    }
    return nullptr;
}

void quad(const aerial::gl::Api& api, float x0, float y0, float x1, float y1) {
    api.Vertex3f(x0, y0, 0.0f);
    api.Vertex3f(x1, y0, 0.0f);
    api.Vertex3f(x1, y1, 0.0f);
    api.Vertex3f(x0, y1, 0.0f);
}

}  // namespace

int text_width(std::string_view text, int scale) { return int(text.size()) * 6 * scale; }

void draw_text(const aerial::gl::Api& api, int viewport_width, int viewport_height, int x, int y,
               int scale, std::string_view text) {
    api.MatrixMode(GL_PROJECTION);
    api.PushMatrix();
    // Pixel grid, y down: x' = 2x/w - 1, y' = 1 - 2y/h.
    const float w = float(viewport_width), h = float(viewport_height);
    const float ortho[16] = {2.0f / w, 0, 0, 0, 0, -2.0f / h, 0, 0, 0, 0, -1, 0, -1, 1, 0, 1};
    api.LoadMatrixf(ortho);
    api.MatrixMode(GL_MODELVIEW);
    api.PushMatrix();
    api.LoadIdentity();
    const GLboolean depth = api.IsEnabled(GL_DEPTH_TEST);
    const GLboolean texture = api.IsEnabled(GL_TEXTURE_2D);
    api.Disable(GL_DEPTH_TEST);
    api.Disable(GL_TEXTURE_2D);
    const float s = float(scale);
    api.Color4f(0.0f, 0.0f, 0.0f, 1.0f);
    api.Begin(GL_QUADS);
    quad(api, float(x) - s, float(y) - s, float(x + text_width(text, scale)) + s, float(y) + 8 * s);
    api.End();
    api.Color4f(1.0f, 1.0f, 1.0f, 1.0f);
    api.Begin(GL_QUADS);
    int cx = x;
    for (char c : text) {
        if (const Glyph* g = find_glyph(c)) {
            for (int row = 0; row < 7; ++row) {
                for (int col = 0; col < 5; ++col) {
                    if (g->rows[row] & (16 >> col)) {
                        const float px = float(cx + col * scale), py = float(y + row * scale);
                        quad(api, px, py, px + s, py + s);
                    }
                }
            }
        }
        cx += 6 * scale;
    }
    api.End();
    if (depth) api.Enable(GL_DEPTH_TEST);
    if (texture) api.Enable(GL_TEXTURE_2D);
    api.MatrixMode(GL_PROJECTION);
    api.PopMatrix();
    api.MatrixMode(GL_MODELVIEW);
    api.PopMatrix();
}

}  // namespace sample
