#include "mcpose/png_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <zlib.h>

#include "mcpose/io_util.h"
#include "test_data.h"

namespace mcpose {
namespace {

using io::Gray16Image;

const std::string kRealDepth = testing::YcbvDir() + "/data/0049/000001-depth.png";
const std::string kRealLabel = testing::YcbvDir() + "/data/0049/000001-label.png";

void ExpectErrorMentions(const Status& status, StatusCode code, const std::string& a,
                         const std::string& b) {
  EXPECT_EQ(status.code(), code) << status.ToString();
  EXPECT_NE(status.message().find(a), std::string::npos) << status.message();
  EXPECT_NE(status.message().find(b), std::string::npos) << status.message();
}

TEST(PngIoTest, Gray16RoundTrip) {
  const auto dir = testing::TempDir("png_gray16");
  Gray16Image image{3, 2, {0, 1, 255, 256, 10000, 65535}};
  const std::string path = (dir / "d.png").string();
  ASSERT_TRUE(io::WriteGray16Png(path, image).ok());
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  StatusOr<Gray16Image> back = io::ReadGray16Png(path);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->width, 3);
  EXPECT_EQ(back->height, 2);
  EXPECT_EQ(back->values, image.values);

  StatusOr<DepthImage> depth = io::ReadDepthPng(path, 1e-4);
  ASSERT_TRUE(depth.ok());
  EXPECT_EQ(depth->at(0, 0), 0.f);
  EXPECT_EQ(depth->at(1, 1), static_cast<float>(10000 * 1e-4));
  EXPECT_EQ(depth->at(2, 1), 0.f);  // saturated: no measurement
}

TEST(PngIoTest, ReadsRealDepth) {
  StatusOr<DepthImage> depth = io::ReadDepthPng(kRealDepth, 1.0 / 10000);
  ASSERT_TRUE(depth.ok()) << depth.status().ToString();
  EXPECT_EQ(depth->width, 640);
  EXPECT_EQ(depth->height, 480);
  ASSERT_EQ(depth->depth_m.size(), 640u * 480u);
  float max_m = 0;
  for (float d : depth->depth_m) max_m = std::max(max_m, d);
  EXPECT_GT(max_m, 0.5f);
  EXPECT_LT(max_m, 6.6f);  // 16-bit range at 0.1 mm
}

TEST(PngIoTest, MaskKeepsEightBitValuesAndRefusesSixteenBit) {
  StatusOr<MaskImage> label = io::ReadMaskPng(kRealLabel);
  ASSERT_TRUE(label.ok()) << label.status().ToString();
  EXPECT_EQ(label->width, 640);
  size_t obj3 = 0;
  for (uint8_t v : label->values) obj3 += (v == 3);
  EXPECT_EQ(obj3, 27218u);  // 004_sugar_box in 0049/000001 (README)

  const auto dir = testing::TempDir("png_mask16");
  const std::string path = (dir / "m.png").string();
  ASSERT_TRUE(io::WriteGray16Png(path, Gray16Image{2, 1, {0, 300}}).ok());
  // A 16-bit image is no label image: refused, not binarised.
  ExpectErrorMentions(io::ReadMaskPng(path).status(), StatusCode::kInvalidArgument, path, "at most 8 bits");
}

TEST(PngIoTest, MissingFileIsNotFound) {
  const std::string path = "/nonexistent/mcpose/depth.png";
  ExpectErrorMentions(io::ReadDepthPng(path, 1e-4).status(), StatusCode::kNotFound, path,
                      "does not exist");
  ExpectErrorMentions(io::ReadMaskPng(path).status(), StatusCode::kNotFound, path,
                      "does not exist");
}

TEST(PngIoTest, NotAPng) {
  const auto dir = testing::TempDir("png_not_png");
  const std::string path = (dir / "x.png").string();
  std::ofstream(path) << "hello, this is text";
  ExpectErrorMentions(io::ReadDepthPng(path, 1e-4).status(), StatusCode::kDataLoss, path,
                      "not a PNG");
}

TEST(PngIoTest, TruncatedPng) {
  const auto dir = testing::TempDir("png_truncated");
  StatusOr<std::string> bytes = io::ReadFileToString(kRealDepth);
  ASSERT_TRUE(bytes.ok());
  // Cut in the header, in the image data, and just before the end chunk.
  for (size_t size : {size_t{20}, bytes->size() / 2, bytes->size() - 6}) {
    const std::string path = (dir / ("cut" + std::to_string(size) + ".png")).string();
    std::ofstream(path, std::ios::binary).write(bytes->data(), static_cast<std::streamsize>(size));
    const Status status = io::ReadDepthPng(path, 1e-4).status();
    ExpectErrorMentions(status, StatusCode::kDataLoss, path, "truncated");
  }
}

TEST(PngIoTest, CorruptPngData) {
  const auto dir = testing::TempDir("png_corrupt");
  StatusOr<std::string> bytes = io::ReadFileToString(kRealDepth);
  ASSERT_TRUE(bytes.ok());
  std::string damaged = *bytes;
  for (size_t i = 200; i < 260; ++i) damaged[i] = static_cast<char>(damaged[i] ^ 0x5a);
  const std::string path = (dir / "bad.png").string();
  std::ofstream(path, std::ios::binary) << damaged;
  const Status status = io::ReadDepthPng(path, 1e-4).status();
  ExpectErrorMentions(status, StatusCode::kDataLoss, path, "PNG");
}

// The zlib checksum at the end of the image data fails, while every chunk's CRC holds: libpng
// notices only after the last row, as a warning; the reader refuses the file.
TEST(PngIoTest, ZlibChecksumThatFailsAfterTheLastRowIsAnError) {
  const auto dir = testing::TempDir("png_adler");
  const std::string good = (dir / "good.png").string();
  io::Gray16Image image{8, 4, std::vector<uint16_t>(32)};
  for (size_t i = 0; i < image.values.size(); ++i) image.values[i] = static_cast<uint16_t>(1000 + 37 * i);
  ASSERT_TRUE(io::WriteGray16Png(good, image).ok());
  StatusOr<std::string> bytes = io::ReadFileToString(good);
  ASSERT_TRUE(bytes.ok());
  std::string damaged = *bytes;
  const size_t idat = damaged.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  auto be32 = [&](size_t at) {
    return (uint32_t{static_cast<uint8_t>(damaged[at])} << 24) | (uint32_t{static_cast<uint8_t>(damaged[at + 1])} << 16) |
           (uint32_t{static_cast<uint8_t>(damaged[at + 2])} << 8) | uint32_t{static_cast<uint8_t>(damaged[at + 3])};
  };
  const uint32_t length = be32(idat - 4);
  damaged[idat + 4 + length - 1] = static_cast<char>(damaged[idat + 4 + length - 1] ^ 0x01);  // the Adler-32's last byte
  const uint32_t crc = static_cast<uint32_t>(
      ::crc32(0, reinterpret_cast<const Bytef*>(damaged.data() + idat), static_cast<uInt>(4 + length)));
  for (int k = 0; k < 4; ++k) damaged[idat + 4 + length + k] = static_cast<char>(crc >> (24 - 8 * k));
  const std::string path = (dir / "adler.png").string();
  std::ofstream(path, std::ios::binary) << damaged;
  ASSERT_TRUE(io::ReadDepthPng(good, 1e-4).ok());
  const Status status = io::ReadDepthPng(path, 1e-4).status();
  ExpectErrorMentions(status, StatusCode::kDataLoss, path, "PNG");
}

TEST(PngIoTest, EightBitDepthIsRefused) {
  const Status status = io::ReadDepthPng(kRealLabel, 1e-4).status();
  ExpectErrorMentions(status, StatusCode::kInvalidArgument, kRealLabel,
                      "depth PNG must be 16-bit single-channel, got 8-bit");
  const std::string color = testing::YcbvDir() + "/data/0049/000001-color.png";
  ExpectErrorMentions(io::ReadDepthPng(color, 1e-4).status(), StatusCode::kInvalidArgument, color,
                      "got 8-bit RGB (3 channels)");
  ExpectErrorMentions(io::ReadMaskPng(color).status(), StatusCode::kInvalidArgument, color,
                      "mask PNG must be single-channel");
}

TEST(PngIoTest, BadDepthScale) {
  ExpectErrorMentions(io::ReadDepthPng(kRealDepth, 0).status(), StatusCode::kInvalidArgument,
                      kRealDepth, "depth scale");
}

TEST(PngIoTest, WriteRefusesWrongSize) {
  const auto dir = testing::TempDir("png_write_size");
  const std::string path = (dir / "m.png").string();
  EXPECT_FALSE(io::WriteMaskPng(path, MaskImage{2, 2, {1, 2, 3}}).ok());
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace mcpose
