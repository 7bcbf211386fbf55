#pragma once
// A minimal PNG encoder (8-bit RGB, no interlace) for scene pictures.
#include <cstdint>
#include <string>
#include <vector>

namespace dash {

/// An RGB raster, rows top to bottom.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3

  RgbImage() = default;
  RgbImage(int w, int h, std::uint8_t grey) : width(w), height(h), rgb(static_cast<std::size_t>(w * h * 3), grey) {}
  void set(int x, int y, std::uint32_t colour);  ///< 0xRRGGBB; ignores pixels outside
  std::uint32_t get(int x, int y) const;
};

/// The PNG file's bytes.
std::string encodePng(const RgbImage& image);
/// Writes encodePng(image); throws InputError if the file cannot be written.
void savePng(const RgbImage& image, const std::string& path);

}  // namespace dash
