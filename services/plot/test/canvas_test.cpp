#include "scanbus/plot/canvas.hpp"

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>

#include "scanbus/plot/cloud_picture.hpp"

using namespace scanbus;
using namespace scanbus::plot;

namespace {

std::string temporary(const std::string& name) { return "/tmp/scanbus_plot_" + std::to_string(getpid()) + name; }

// A written PNG, read back with cairo: its size and pixels (0xRRGGBB).
class Png {
 public:
  explicit Png(const std::string& path) : surface_(cairo_image_surface_create_from_png(path.c_str())) {}
  ~Png() { cairo_surface_destroy(surface_); }
  bool ok() const { return cairo_surface_status(surface_) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_); }
  int height() const { return cairo_image_surface_get_height(surface_); }
  uint32_t at(int x, int y) const {
    const auto* row = cairo_image_surface_get_data(surface_) + y * cairo_image_surface_get_stride(surface_);
    return reinterpret_cast<const uint32_t*>(row)[x] & 0xFFFFFF;
  }

 private:
  cairo_surface_t* surface_;
};

}  // namespace

TEST(Canvas, ASquarePlanKeepsMetresEqualBothWays) {
  Canvas canvas(temporary("square.png"), {0, 0}, {4, 2});  // 800 px, margins 60
  EXPECT_DOUBLE_EQ(canvas.scale(), 680.0 / 4);
  EXPECT_EQ(canvas.width(), 800);
  EXPECT_EQ(canvas.height(), 800);
  // 2 m high: 340 px, in the middle of the 680 px between the margins.
  EXPECT_TRUE(canvas.pixel({0, 0}).isApprox(Eigen::Vector2d(60, 570)));
  EXPECT_TRUE(canvas.pixel({4, 2}).isApprox(Eigen::Vector2d(740, 230)));  // y up
}

TEST(Canvas, AFittedPictureTakesTheBoxsShape) {
  Layout layout;
  layout.square = false;
  layout.margin = 40;
  layout.min_height = 240;
  Canvas wide(temporary("wide.png"), {-1, 0}, {9, 1}, layout);
  EXPECT_EQ(wide.width(), 800);
  EXPECT_EQ(wide.height(), 240);                                             // 72 + 80 px would be too low for its text
  EXPECT_TRUE(wide.pixel({-1, 0}).isApprox(Eigen::Vector2d(40, 200 - 44)));  // centred in the 160 px
}

TEST(Canvas, WhatIsDrawnIsWhereTheWorldSaysAndSaved) {
  const std::string path = temporary("dots.png");
  {
    Canvas canvas(path, {0, 0}, {10, 10});
    canvas.grid();
    canvas.dot({2, 3}, 4, Colour::hex(0xFF0000));
    canvas.squares({{7, 7}}, 6, Colour::hex(0x0000FF));
    canvas.save();
  }
  const Png png(path);
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(png.width(), 800);
  EXPECT_EQ(png.at(60 + 2 * 68, 740 - 3 * 68), 0xFF0000u);
  EXPECT_EQ(png.at(60 + 7 * 68, 740 - 7 * 68), 0x0000FFu);
  EXPECT_EQ(png.at(60 + 5 * 68 + 30, 740 - 5 * 68 - 30), 0xFFFFFFu);  // between grid lines: white
  std::remove(path.c_str());
}

TEST(Canvas, ASvgPathWritesSvg) {
  const std::string path = temporary("plan.svg");
  {
    Canvas canvas(path, {0, 0}, {1, 1});
    canvas.line({0, 0}, {1, 1}, Colour::grey(0), 2, true);
    canvas.heading("a room");
    canvas.save();
  }
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text.rfind("<?xml", 0), 0u);
  EXPECT_NE(text.find("<svg"), std::string::npos);
  std::remove(path.c_str());
}

// A status message or a title longer than the picture is set smaller, then cut: never past
// the right edge.
TEST(Canvas, LongTextStaysOnThePicture) {
  const std::string path = temporary("long.png");
  {
    Canvas canvas(path, {0, 0}, {1, 1});
    std::string title;
    for (int i = 0; i < 40; ++i) title += "a long status message \u00b1 ";
    canvas.heading(title, title);
    canvas.legend(title);
    canvas.save();
  }
  const Png png(path);
  ASSERT_TRUE(png.ok());
  for (int y = 0; y < png.height(); ++y)
    for (int x = png.width() - 6; x < png.width(); ++x) ASSERT_EQ(png.at(x, y), 0xFFFFFFu) << x << ", " << y;
  std::remove(path.c_str());
}

TEST(Canvas, AFileThatCannotBeWrittenIsNamed) {
  Canvas canvas("/nonexistent/folder/plan.png", {0, 0}, {1, 1});
  try {
    canvas.save();
    FAIL() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/folder/plan.png"), std::string::npos) << error.what();
  }
}

TEST(CloudPicture, AnEmptyCloudIsAnErrorNotAPicture) {
  EXPECT_THROW(write_cloud_picture(temporary("empty.png"), {}, "empty", CloudView::Top, false), std::runtime_error);
}

TEST(Canvas, APictureEndsWhenSaved) {
  const std::string path = temporary("once.png");
  Canvas canvas(path, {0, 0}, {1, 1});
  canvas.save();
  EXPECT_THROW(canvas.dot({0.5, 0.5}, 2, Colour::grey(0)), std::logic_error);
  EXPECT_THROW(canvas.save(), std::logic_error);
  std::remove(path.c_str());
}

// Text cairo cannot show (not UTF-8: a Latin-1 file name as the title) would put the picture
// in error and drop all drawn after it: the bad byte becomes '?' instead.
TEST(Canvas, TextThatIsNotUtf8CostsNothing) {
  const std::string path = temporary("latin1.png");
  {
    Canvas canvas(path, {0, 0}, {10, 10});
    canvas.heading("caf\xe9.pcd \xe2\x80", "\xff");
    canvas.dot({5, 5}, 4, Colour::hex(0xFF0000));
    canvas.save();
  }
  const Png png(path);
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(png.at(60 + 5 * 68, 740 - 5 * 68), 0xFF0000u);
  std::remove(path.c_str());
}

TEST(Canvas, AnUnsavedSvgLeavesNoFile) {
  const std::string path = temporary("unsaved.svg");
  { Canvas canvas(path, {0, 0}, {1, 1}); }
  EXPECT_NE(access(path.c_str(), F_OK), 0);
}
