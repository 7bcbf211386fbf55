#include "engine/scenarios/png_writer.h"

#include <zlib.h>

#include <fstream>

#include "engine/core/check.h"

namespace dash {

namespace {

void put32(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((v >> shift) & 0xffu));
}

void chunk(std::string& out, const char* type, const std::string& data) {
  put32(out, static_cast<std::uint32_t>(data.size()));
  std::string body(type, 4);
  body += data;
  out += body;
  const auto crc = crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()));
  put32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

void RgbImage::set(int x, int y, std::uint32_t colour) {
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  const auto i = static_cast<std::size_t>((y * width + x) * 3);
  rgb[i] = static_cast<std::uint8_t>((colour >> 16) & 0xffu);
  rgb[i + 1] = static_cast<std::uint8_t>((colour >> 8) & 0xffu);
  rgb[i + 2] = static_cast<std::uint8_t>(colour & 0xffu);
}

std::uint32_t RgbImage::get(int x, int y) const {
  const auto i = static_cast<std::size_t>((y * width + x) * 3);
  return (static_cast<std::uint32_t>(rgb[i]) << 16) | (static_cast<std::uint32_t>(rgb[i + 1]) << 8) | rgb[i + 2];
}

std::string encodePng(const RgbImage& image) {
  DASH_DEMAND(image.width > 0 && image.height > 0);
  // Each row: filter type 0 (none), then the row's bytes.
  std::string raw;
  const auto row_bytes = static_cast<std::size_t>(image.width) * 3;
  raw.reserve((row_bytes + 1) * static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(image.rgb.data()) + static_cast<std::size_t>(y) * row_bytes, row_bytes);
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(size, '\0');
  const int rc = compress2(reinterpret_cast<Bytef*>(packed.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                           static_cast<uLong>(raw.size()), Z_BEST_COMPRESSION);
  DASH_DEMAND_MSG(rc == Z_OK, "zlib compress2 failed");
  packed.resize(size);

  std::string out("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  put32(header, static_cast<std::uint32_t>(image.width));
  put32(header, static_cast<std::uint32_t>(image.height));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filtering, no interlace
  chunk(out, "IHDR", header);
  chunk(out, "IDAT", packed);
  chunk(out, "IEND", "");
  return out;
}

void savePng(const RgbImage& image, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  DASH_THROW_UNLESS(out.good(), path + ": cannot write the picture");
  out << encodePng(image);
  out.flush();
  DASH_THROW_UNLESS(out.good(), path + ": writing the picture failed");
}

}  // namespace dash
