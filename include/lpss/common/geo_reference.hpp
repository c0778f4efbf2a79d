// Where a world is on the Earth: how its global coordinates map to geocentric (ECEF, WGS84) metres. The
// engine never uses it; it travels with the world's settings for clients that speak geocentric
// coordinates, as a DIS gateway does.
#pragma once

#include <cstdint>

namespace lpss {

struct GeoReference {
    enum class Frame : std::uint8_t {
        none = 0,           ///< not placed on the Earth
        ecef = 1,           ///< global coordinates are ECEF metres
        local_tangent = 2,  ///< global axes east, north, up at (latitude, longitude, height), the origin
    };
    Frame frame = Frame::none;
    double latitude_deg = 0.0;
    double longitude_deg = 0.0;
    double height_m = 0.0;
};

}  // namespace lpss
