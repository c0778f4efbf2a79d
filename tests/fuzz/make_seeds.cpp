// Writes seed inputs for a fuzz target into a folder, serialized in CDR as Fast DDS hands them to the type:
// for sector_frames, sequences of real sector samples (complete and partial, with bodies, kinds and
// departures) joined by the target's marker; for command, one command of each kind.
// usage: lpss_fuzz_seeds sector_frames|command FOLDER
#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "lpss.h"
#include "lpss_dds/convert.hpp"

namespace {

template <class T>
std::string serialize(const T& sample) {
    std::vector<char> bytes(T::getCdrSerializedSize(sample) + 4);
    eprosima::fastcdr::FastBuffer buffer(bytes.data(), bytes.size());
    eprosima::fastcdr::Cdr cdr(buffer, eprosima::fastcdr::Cdr::DEFAULT_ENDIAN,
                               eprosima::fastcdr::Cdr::DDS_CDR);
    cdr.serialize_encapsulation();
    sample.serialize(cdr);
    return std::string(bytes.data(), cdr.getSerializedDataLength());
}

lpss::wire::SectorFrame sample(std::uint64_t frame, std::uint64_t base, bool complete, std::int64_t i) {
    lpss::wire::SectorFrame f;
    f.worker(1);
    f.sector(lpss::dds::to_wire(lpss::SectorKey{i, 0, -1}));
    f.recipients({1, 2});
    f.frame(frame);
    f.base(base);
    f.epoch(1);
    f.complete(complete);
    for (lpss::BodyId id : {lpss::BodyId{7}, lpss::BodyId{9}}) {
        lpss::BodySnapshot b;
        b.id = id;
        b.position = lpss::SectorPosition{{i, 0, -1}, Eigen::Vector3d(1.5 * static_cast<double>(id), 2, -3)};
        b.linear_velocity = Eigen::Vector3d(0.5, 0, 0);
        f.bodies().push_back(lpss::dds::to_wire(b));
        lpss::wire::BodyKind kind;
        kind.id(id);
        kind.name("body" + std::to_string(id));
        kind.shape(id % 2);
        kind.size().x(0.5);
        kind.size().y(0.5);
        kind.size().z(0.5);
        kind.mass(1.0);
        f.kinds().push_back(kind);
        f.offsets().push_back(lpss::wire::Vec3d());
    }
    if (!complete) f.departed({3});
    return f;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s sector_frames|command FOLDER\n", argv[0]);
        return 2;
    }
    const std::string target = argv[1], folder = argv[2];
    if (target == "command") {
        int n = 0;
        for (std::uint8_t kind :
             {lpss::wire::kCommandSpawn, lpss::wire::kCommandRemove, lpss::wire::kCommandImpulse,
              lpss::wire::kCommandSetVelocity, std::uint8_t{9}}) {
            lpss::wire::Command c;
            c.client("seed");
            c.request(1);
            c.kind(kind);
            c.body(1);
            c.vector1().x(2.0);
            c.vector2().y(-1.0);
            if (kind == lpss::wire::kCommandSpawn) {
                lpss::BodyDesc body;
                body.id = 40;
                body.mass = 1.0;
                body.shape = lpss::Sphere{0.5};
                lpss::BodySnapshot at;
                at.position = lpss::SectorPosition{{3, 0, -2}, Eigen::Vector3d(1, 2, 3)};
                c.body(40);
                c.spawn(lpss::dds::describe(body, at));
            }
            std::ofstream(folder + "/seed-" + std::to_string(n++)) << serialize(c);
        }
        return 0;
    }
    if (target != "sector_frames") {
        std::fprintf(stderr, "no seeds for '%s'\n", target.c_str());
        return 2;
    }
    const std::string marker = "\xFF\xFE\xFD\xFC";
    const std::vector<std::vector<lpss::wire::SectorFrame>> seeds = {
        {sample(1, 1, true, 0)},
        {sample(1, 1, true, 0), sample(2, 1, false, 0), sample(3, 2, false, 0)},
        {sample(5, 5, true, 3), sample(5, 5, true, 4), sample(6, 5, false, 3), sample(6, 6, true, 4)},
    };
    for (std::size_t n = 0; n < seeds.size(); ++n) {
        std::string bytes;
        for (const auto& s : seeds[n])
            bytes += (bytes.empty() ? "" : marker) + serialize(s);
        std::ofstream(folder + "/seed-" + std::to_string(n)) << bytes;
    }
    return 0;
}
