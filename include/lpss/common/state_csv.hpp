// The body-state CSV written by lpss-sim and lpss-watch, so runs of either can be compared row by row:
// frame,id,x,y,z,qx,qy,qz,qw,vx,vy,vz,si,sj,sk,lx,ly,lz with numbers at 17 significant digits.
#pragma once

#include <cstdint>
#include <cstdio>

#include "lpss/common/body_snapshot.hpp"

namespace lpss {

/// Writes the header line.
void write_state_csv_header(std::FILE* out);

/// Writes one body of one frame; x,y,z is the double global position made with `grid`.
void write_state_csv_row(std::FILE* out, std::uint64_t frame, const BodySnapshot& body,
                         const SectorGrid& grid);

}  // namespace lpss
