#include "lpss/common/state_csv.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

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

Expected<std::vector<StateCsvRow>> read_state_csv(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Error{path + ": cannot open the state CSV"};
    std::vector<StateCsvRow> rows;
    std::string line;
    std::getline(in, line);  // the header
    for (std::size_t number = 2; std::getline(in, line); ++number) {
        std::istringstream row(line);
        std::vector<std::string> f;
        for (std::string cell; std::getline(row, cell, ',');)
            f.push_back(cell);
        if (f.size() != 18) return Error{path + ":" + std::to_string(number) + ": not 18 fields: " + line};
        try {
            StateCsvRow r;
            r.frame = std::stoull(f[0]);
            r.body.id = std::stoull(f[1]);
            r.global = Eigen::Vector3d(std::stod(f[2]), std::stod(f[3]), std::stod(f[4]));
            r.body.orientation =
                Eigen::Quaterniond(std::stod(f[8]), std::stod(f[5]), std::stod(f[6]), std::stod(f[7]));
            r.body.linear_velocity = Eigen::Vector3d(std::stod(f[9]), std::stod(f[10]), std::stod(f[11]));
            r.body.position = SectorPosition{{std::stoll(f[12]), std::stoll(f[13]), std::stoll(f[14])},
                                             {std::stod(f[15]), std::stod(f[16]), std::stod(f[17])}};
            rows.push_back(r);
        } catch (const std::exception&) {
            return Error{path + ":" + std::to_string(number) + ": a field is not a number: " + line};
        }
    }
    return rows;
}

}  // namespace lpss
