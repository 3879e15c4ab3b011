// The elevation grid as a GeoTIFF (GDAL) that gdalinfo, QGIS and every GIS open: band 1
// the height above the WGS84 ellipsoid (m), band 2 the spread of the cell's point heights
// (m), band 3 the cell's point count; empty cells are no data (NaN).
#pragma once

#include <stdexcept>
#include <string>

#include "scanbus/cloud_assembly/elevation_grid.hpp"

namespace scanbus::cloud_dem {

// Where the map frame's origin is on the earth (its x east, y north, z up): a GPS fix's
// latitude and longitude (degrees, WGS84) and altitude (m above the ellipsoid).
struct GeoOrigin {
  double latitude = 0, longitude = 0, altitude = 0;
};

struct GeoTiffError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The grid in a transverse Mercator projection centred on the origin (scale 1 there, false
// easting and northing 0), so the map frame's x and y are the raster's coordinates: they
// differ by less than a millimetre within 3 km (8 mm at 10 km). Heights are converted from the map's
// local tangent plane to the ellipsoid cell by cell (the plane rises 8 cm above it 1 km out).
// Throws GeoTiffError naming the file and GDAL's message; an origin off the earth is refused.
void write_geotiff(const std::string& path, const cloud_assembly::ElevationGrid& grid, const GeoOrigin& origin);

}  // namespace scanbus::cloud_dem
