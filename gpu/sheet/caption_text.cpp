#include "gpu/sheet/caption_text.h"

#include <algorithm>
#include <cmath>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_easy_font.h>  // header only; every function static
#pragma GCC diagnostic pop

namespace sweepd::sheet {

namespace {

struct FontVertex {
  float x, y, z;
  unsigned char colour[4];
};

}  // namespace

void draw_text(std::span<std::uint8_t> rgba, int width, int height, int x, int y,
               const std::string& text, std::array<std::uint8_t, 3> colour, int scale) {
  std::string buffer = text;  // stb_easy_font takes char* and knows ASCII 32-126 only
  for (char& c : buffer)
    if (c != '\n' && (c < 32 || c > 126)) c = '?';
  // At most 16 strokes (quads of 4 vertices) per character: 64 vertices, room for any glyph.
  std::vector<FontVertex> vertices((buffer.size() + 1) * 64);
  const int quads = stb_easy_font_print(0.0f, 0.0f, buffer.data(), nullptr, vertices.data(),
                                        static_cast<int>(vertices.size() * sizeof(FontVertex)));
  for (int q = 0; q < quads; ++q) {
    const FontVertex* corner = &vertices[4 * static_cast<std::size_t>(q)];
    // Quads are axis-aligned: corners 0 and 2 are opposite.
    const int x0 = std::max(0, x + static_cast<int>(std::lround(corner[0].x * scale)));
    const int y0 = std::max(0, y + static_cast<int>(std::lround(corner[0].y * scale)));
    const int x1 = std::min(width, x + static_cast<int>(std::lround(corner[2].x * scale)));
    const int y1 = std::min(height, y + static_cast<int>(std::lround(corner[2].y * scale)));
    for (int row = y0; row < y1; ++row)
      for (int column = x0; column < x1; ++column) {
        std::uint8_t* pixel = &rgba[(static_cast<std::size_t>(row) * width + column) * 4];
        pixel[0] = colour[0], pixel[1] = colour[1], pixel[2] = colour[2], pixel[3] = 255;
      }
  }
}

int text_width(const std::string& text, int scale) {
  std::string buffer = text;
  return stb_easy_font_width(buffer.data()) * scale;
}

}  // namespace sweepd::sheet
