// The body-state CSV written by lpss-sim and lpss-watch, so runs of either can be compared row by row:
// frame,id,x,y,z,qx,qy,qz,qw,vx,vy,vz,si,sj,sk,lx,ly,lz with numbers at 17 significant digits.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "lpss/common/body_snapshot.hpp"
#include "lpss/common/expected.hpp"

namespace lpss {

/// Writes the header line.
void write_state_csv_header(std::FILE* out);

/// Writes one body of one frame; x,y,z is the double global position made with `grid`.
void write_state_csv_row(std::FILE* out, std::uint64_t frame, const BodySnapshot& body,
                         const SectorGrid& grid);

/// One row read back: the frame, the body (the CSV holds no angular velocity nor awake flag) and its
/// global position as written.
struct StateCsvRow {
    std::uint64_t frame = 0;
    BodySnapshot body;
    Eigen::Vector3d global = Eigen::Vector3d::Zero();
};

/// Reads a whole file written as above; refused with the path and the line that does not parse.
Expected<std::vector<StateCsvRow>> read_state_csv(const std::string& path);

}  // namespace lpss
