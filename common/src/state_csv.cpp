#include "lpss/common/state_csv.hpp"

#include <fmt/format.h>

namespace lpss {

void write_state_csv_header(std::FILE* out) {
    std::fputs("frame,id,x,y,z,qx,qy,qz,qw,vx,vy,vz,si,sj,sk,lx,ly,lz\n", out);
}

void write_state_csv_row(std::FILE* out, std::uint64_t frame, const BodySnapshot& b, const SectorGrid& grid) {
    Eigen::Vector3d g = grid.to_global(b.position);
    const Eigen::Quaterniond& q = b.orientation;
    const Eigen::Vector3d& v = b.linear_velocity;
    const SectorPosition& p = b.position;
    fmt::print(out,
               "{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{},{},{"
               "},{:.17g},{:."
               "17g},{:.17g}\n",
               frame, b.id, g.x(), g.y(), g.z(), q.x(), q.y(), q.z(), q.w(), v.x(), v.y(), v.z(), p.sector.i,
               p.sector.j, p.sector.k, p.local.x(), p.local.y(), p.local.z());
}

}  // namespace lpss
