// The GeoTIFF read back through GDAL: georeference, bands and heights on the ellipsoid.
#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "scanbus/cloud_dem/geotiff.hpp"

using namespace scanbus;

namespace {

cloud_assembly::ElevationGrid level_grid(double height) {
  std::vector<Eigen::Vector3f> points;
  for (double x = -999.5; x < 1000; x += 5)
    for (double y = -199.5; y < 200; y += 5)
      for (int k = 0; k < 3; ++k) points.emplace_back(x, y, height + 0.01 * (k - 1));
  return cloud_assembly::grid_elevation(points, {10.0, 3});
}

std::string temporary(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::to_string(getpid()) + name)).string();
}

}  // namespace

TEST(GeoTiff, ReadsBackGeoreferencedWithHeightsOnTheEllipsoid) {
  const cloud_dem::GeoOrigin origin{47.3977, 8.5456, 488.0};
  const auto grid = level_grid(2.0);
  const std::string path = temporary("_dem.tif");
  cloud_dem::write_geotiff(path, grid, origin);
  GDALAllRegister();
  std::unique_ptr<GDALDataset> dataset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  ASSERT_TRUE(dataset);
  ASSERT_EQ(dataset->GetRasterCount(), 3);
  EXPECT_EQ(dataset->GetRasterXSize(), 200);
  EXPECT_EQ(dataset->GetRasterYSize(), 40);
  double transform[6];
  ASSERT_EQ(dataset->GetGeoTransform(transform), CE_None);
  EXPECT_DOUBLE_EQ(transform[0], -1000.0);
  EXPECT_DOUBLE_EQ(transform[3], 200.0);
  EXPECT_DOUBLE_EQ(transform[1], 10.0);
  EXPECT_DOUBLE_EQ(transform[5], -10.0);

  // The raster's corner, taken to latitude and longitude by GDAL's own transformation,
  // lies where the map frame's point is (1 km west and 200 m north of the origin).
  OGRSpatialReference projected(dataset->GetProjectionRef()), geographic;
  geographic.SetWellKnownGeogCS("WGS84");
  geographic.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  projected.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_degrees(OGRCreateCoordinateTransformation(&projected, &geographic));
  ASSERT_TRUE(to_degrees);
  double x = transform[0], y = transform[3];
  ASSERT_TRUE(to_degrees->Transform(1, &x, &y));
  constexpr double kMetresPerDegree = 111195;  // along a meridian
  EXPECT_NEAR((y - origin.latitude) * kMetresPerDegree, 200.0, 1.0);
  EXPECT_NEAR((x - origin.longitude) * kMetresPerDegree * std::cos(origin.latitude * M_PI / 180), -1000.0, 3.0);

  std::vector<float> heights(200 * 40), spread(200 * 40);
  ASSERT_EQ(dataset->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 200, 40, heights.data(), 200, 40, GDT_Float32, 0, 0),
            CE_None);
  ASSERT_EQ(dataset->GetRasterBand(2)->RasterIO(GF_Read, 0, 0, 200, 40, spread.data(), 200, 40, GDT_Float32, 0, 0),
            CE_None);
  EXPECT_STREQ(dataset->GetRasterBand(1)->GetDescription(), "height");
  int has_nodata = 0;
  EXPECT_TRUE(std::isnan(dataset->GetRasterBand(1)->GetNoDataValue(&has_nodata)));
  EXPECT_TRUE(has_nodata);
  // Next to the origin the height is the origin's altitude plus the map's z; 1 km out the
  // tangent plane is d^2 / 2R = 7.9 cm above the ellipsoid.
  const size_t centre = grid.index(20, 100), corner = grid.index(0, 0);
  EXPECT_NEAR(heights[centre], 490.0, 0.002);
  EXPECT_NEAR(heights[corner] - 490.0, std::hypot(995.0, 195.0) * std::hypot(995.0, 195.0) / (2 * 6371000), 0.005);
  EXPECT_NEAR(spread[centre], 0.01 * std::sqrt(2.0 / 3.0), 1e-4);
  dataset.reset();
  std::filesystem::remove(path);
}

TEST(GeoTiff, BadOriginsAndPathsAreRefusedWithTheReason) {
  const auto grid = level_grid(0.0);
  EXPECT_THROW(cloud_dem::write_geotiff(temporary("_bad.tif"), grid, {91, 0, 0}), cloud_dem::GeoTiffError);
  EXPECT_THROW(cloud_dem::write_geotiff(temporary("_bad.tif"), grid, {0, 0, NAN}), cloud_dem::GeoTiffError);
  try {
    cloud_dem::write_geotiff("/nonexistent/folder/dem.tif", grid, {47, 8, 400});
    FAIL() << "no folder, no file";
  } catch (const cloud_dem::GeoTiffError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/folder/dem.tif"), std::string::npos) << e.what();
  }
}
