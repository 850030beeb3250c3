// draw_text: captions on pictures (contact sheets), in stb_easy_font's built-in bitmap font
// (Debian's libstb, already a dependency for PNG writing; no font file to find or ship).
//
// Inputs: rgba W·H·4 bytes, row 0 = top (as gpu::PreviewRenderer writes it); the text's
//   top-left corner (x, y) in pixels; ASCII text (other characters show as ?; '\n' starts a line);
//   an RGB colour; scale, a whole magnification (the font's glyphs are 5×7 pixel strokes at scale
//   1, 6 per character wide, lines 12 apart). Pixels outside the image are skipped.
// text_width: the text's width in pixels at that scale.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace sweepd::sheet {

void draw_text(std::span<std::uint8_t> rgba, int width, int height, int x, int y,
               const std::string& text, std::array<std::uint8_t, 3> colour, int scale);

int text_width(const std::string& text, int scale);

}  // namespace sweepd::sheet
