#include "lpss_dds/sample_check.hpp"

#include <spdlog/spdlog.h>

#include <cctype>
#include <cmath>

#include "lpss/common/sector_key.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::dds {
namespace {

bool finite(const wire::Vec3f& v) {
    return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

bool finite(const wire::Vec3d& v) {
    return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

std::string where(const wire::SectorFrame& s) {
    return "sample of sector (" + std::to_string(s.sector().i()) + ", " + std::to_string(s.sector().j()) +
           ", " + std::to_string(s.sector().k()) + ") frame " + std::to_string(s.frame()) + " from worker " +
           std::to_string(s.worker());
}

}  // namespace

std::string implausible(const wire::SectorFrame& s, std::uint64_t newest_frame, std::uint64_t frames_ahead) {
    if (!in_range(from_wire(s.sector()))) return where(s) + ": sector index beyond 2^62";
    if (s.frame() > newest_frame && s.frame() - newest_frame > frames_ahead) {
        return where(s) + ": frame is ahead of the newest started (" + std::to_string(newest_frame) + ")";
    }
    if (s.base() > s.frame() || (s.complete() && s.base() != s.frame()))
        return where(s) + ": base frame " + std::to_string(s.base()) + " does not fit its frame";
    if (s.complete() && s.kinds().size() != s.bodies().size())
        return where(s) + ": a complete sample needs a kind for every body";
    if (s.kinds().size() > s.bodies().size()) return where(s) + ": more kinds than bodies";
    if (!s.offsets().empty() && s.offsets().size() != s.bodies().size())
        return where(s) + ": offsets do not match its bodies";
    if (!s.ranks().empty() && s.ranks().size() != s.bodies().size())
        return where(s) + ": ranks do not match its bodies";
    for (const wire::BodyState& b : s.bodies()) {
        const wire::Quatf& q = b.orientation();
        const bool quaternion = std::isfinite(q.x()) && std::isfinite(q.y()) && std::isfinite(q.z()) &&
                                std::isfinite(q.w()) &&
                                q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w() > 1e-12f;
        if (!finite(b.position()) || !finite(b.linear_velocity()) || !finite(b.angular_velocity()) ||
            !quaternion)
            return where(s) + ": body " + std::to_string(b.id()) + " has a state that is not finite";
    }
    for (const wire::Vec3d& offset : s.offsets()) {
        if (!finite(offset)) return where(s) + ": an offset is not finite";
    }
    return {};
}

void RefusedSamples::refuse(const std::string& why) {
    ++count_;
    std::string kind;
    for (std::size_t n = why.find(": "); n != std::string::npos && n < why.size(); ++n) {
        if (!std::isdigit(static_cast<unsigned char>(why[n]))) kind += why[n];
    }
    const auto now = std::chrono::steady_clock::now();
    auto [at, first] = logged_.try_emplace(kind, now);
    if (!first && now - at->second < std::chrono::seconds(1)) return;
    at->second = now;
    spdlog::warn("{}: refused a sector {} ({} refused so far)", reader_, why, count_);
}

}  // namespace lpss::dds
