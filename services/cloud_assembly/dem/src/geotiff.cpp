#include "scanbus/cloud_dem/geotiff.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <GeographicLib/LocalCartesian.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>

namespace scanbus::cloud_dem {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* dataset) const { GDALClose(dataset); }
};

// GDAL reports through a global handler: quiet it and turn its last message into our error.
std::string gdal_message() {
  const std::string message = CPLGetLastErrorMsg();
  return message.empty() ? "no reason given" : message;
}

std::string projection_wkt(const GeoOrigin& origin) {
  OGRSpatialReference srs;
  srs.SetProjCS("Transverse Mercator at the scanbus map origin");
  srs.SetWellKnownGeogCS("WGS84");
  srs.SetTM(origin.latitude, origin.longitude, 1.0, 0.0, 0.0);
  srs.SetLinearUnits(SRS_UL_METER, 1.0);
  char* text = nullptr;
  if (srs.exportToWkt(&text) != OGRERR_NONE) throw GeoTiffError("cannot describe the projection: " + gdal_message());
  std::string wkt = text;
  CPLFree(text);
  return wkt;
}

// Heights on the ellipsoid: each cell centre's map point taken back through the tangent plane.
std::vector<float> ellipsoid_heights(const cloud_assembly::ElevationGrid& grid, const GeoOrigin& origin) {
  const GeographicLib::LocalCartesian tangent(origin.latitude, origin.longitude, origin.altitude);
  std::vector<float> heights(grid.height.size(), std::numeric_limits<float>::quiet_NaN());
  for (size_t row = 0; row < grid.rows; ++row)
    for (size_t column = 0; column < grid.columns; ++column) {
      const size_t i = grid.index(row, column);
      if (!std::isfinite(grid.height[i])) continue;
      const Eigen::Vector2d xy = grid.centre(row, column);
      double latitude, longitude, height;
      tangent.Reverse(xy.x(), xy.y(), grid.height[i], latitude, longitude, height);
      heights[i] = static_cast<float>(height);
    }
  return heights;
}

void write_band(GDALDataset& dataset, int number, const char* name, const char* unit, std::vector<float> values,
                const cloud_assembly::ElevationGrid& grid, const std::string& path) {
  GDALRasterBand* band = dataset.GetRasterBand(number);
  band->SetDescription(name);
  if (*unit) band->SetUnitType(unit);
  band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  if (band->RasterIO(GF_Write, 0, 0, static_cast<int>(grid.columns), static_cast<int>(grid.rows), values.data(),
                     static_cast<int>(grid.columns), static_cast<int>(grid.rows), GDT_Float32, 0, 0) != CE_None)
    throw GeoTiffError(path + ": cannot write band '" + name + "': " + gdal_message());
}

}  // namespace

void write_geotiff(const std::string& path, const cloud_assembly::ElevationGrid& grid, const GeoOrigin& origin) {
  if (!(std::abs(origin.latitude) <= 90) || !(std::abs(origin.longitude) <= 180) || !std::isfinite(origin.altitude))
    throw GeoTiffError("origin " + std::to_string(origin.latitude) + ", " + std::to_string(origin.longitude) + ", " +
                       std::to_string(origin.altitude) +
                       ": latitude must be within +-90 degrees, longitude +-180, altitude finite");
  if (grid.columns == 0 || grid.rows == 0) throw GeoTiffError(path + ": the grid has no cells");
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  CPLPushErrorHandler(CPLQuietErrorHandler);
  struct PopHandler {
    ~PopHandler() { CPLPopErrorHandler(); }
  } pop;
  CPLErrorReset();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw GeoTiffError("GDAL has no GTiff driver");
  char** options = CSLSetNameValue(nullptr, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "TILED", "YES");
  std::unique_ptr<GDALDataset, DatasetCloser> dataset(driver->Create(
      path.c_str(), static_cast<int>(grid.columns), static_cast<int>(grid.rows), 3, GDT_Float32, options));
  CSLDestroy(options);
  if (!dataset) throw GeoTiffError(path + ": cannot create: " + gdal_message());
  double transform[6] = {grid.west, grid.cell_size, 0, grid.north, 0, -grid.cell_size};
  if (dataset->SetGeoTransform(transform) != CE_None ||
      dataset->SetProjection(projection_wkt(origin).c_str()) != CE_None)
    throw GeoTiffError(path + ": cannot georeference: " + gdal_message());
  char origin_text[96];  // 1e-9 degrees: 0.1 mm
  std::snprintf(origin_text, sizeof origin_text, "%.9f %.9f %.4f", origin.latitude, origin.longitude, origin.altitude);
  dataset->SetMetadataItem("SCANBUS_ORIGIN", origin_text);
  write_band(*dataset, 1, "height", "m", ellipsoid_heights(grid, origin), grid, path);
  write_band(*dataset, 2, "stdev", "m", grid.stdev, grid, path);
  write_band(*dataset, 3, "count", "", std::vector<float>(grid.count.begin(), grid.count.end()), grid, path);
  dataset.reset();  // closing writes what is still cached (GDAL 3.6 reports a failure only as the last error)
  if (CPLGetLastErrorType() >= CE_Failure) throw GeoTiffError(path + ": cannot finish writing: " + gdal_message());
}

}  // namespace scanbus::cloud_dem
