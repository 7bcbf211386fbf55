#include "engine/scenarios/scene_picture.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include "scenario_test_util.h"

namespace dash {
namespace {

std::uint32_t read32(const std::string& s, std::size_t at) {
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3]));
}

TEST(ScenePicture, PngChunksAreWellFormedAndDecodeToTheImage) {
  RgbImage image(7, 5, 0x10);
  image.set(3, 2, 0xff0000);
  const std::string png = encodePng(image);
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::size_t at = 8;
  std::string idat;
  std::vector<std::string> types;
  while (at < png.size()) {
    const std::uint32_t length = read32(png, at);
    const std::string type = png.substr(at + 4, 4);
    const std::string body = png.substr(at + 4, 4 + length);
    EXPECT_EQ(read32(png, at + 8 + length),
              static_cast<std::uint32_t>(
                  crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))))
        << type;
    if (type == "IDAT") idat += png.substr(at + 8, length);
    types.push_back(type);
    at += 12 + length;
  }
  EXPECT_EQ(types, (std::vector<std::string>{"IHDR", "IDAT", "IEND"}));
  std::string raw(static_cast<std::size_t>(5 * (1 + 7 * 3)), '\0');
  uLongf size = static_cast<uLongf>(raw.size());
  ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(raw.data()), &size, reinterpret_cast<const Bytef*>(idat.data()),
                       static_cast<uLong>(idat.size())),
            Z_OK);
  EXPECT_EQ(size, raw.size());
  const std::size_t red = 2 * (1 + 21) + 1 + 3 * 3;  // row 2, after its filter byte, pixel 3
  EXPECT_EQ(static_cast<unsigned char>(raw[red]), 0xff);
  EXPECT_EQ(static_cast<unsigned char>(raw[red + 1]), 0x00);
}

TEST(ScenePicture, EveryFamilyRendersWithObjectsInColour) {
  for (const auto& f : scenarioFamilies()) {
    const auto g = test::generate(f.name, {}, 1);
    const RgbImage image = renderScene(g.scene, {.max_side_pixels = 400});
    EXPECT_EQ(std::max(image.width, image.height), 400) << f.name;
    int coloured = 0;  // pixels whose channels differ: objects, robots, boxes (the rest is grey)
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const std::uint32_t c = image.get(x, y);
        coloured += ((c >> 16) & 0xff) != (c & 0xff) ? 1 : 0;
      }
    }
    EXPECT_GT(coloured, 50) << f.name;
    EXPECT_EQ(encodePng(image), encodePng(renderScene(g.scene, {.max_side_pixels = 400}))) << f.name;
  }
}

}  // namespace
}  // namespace dash
