// What a reader refuses of a sector sample before it reaches the chain: without DDS Security any peer on
// the domain can write to lpss/sector_frames, and one sample with a frame far in the future would make
// every later sample of its sector stale to the chain (the sector frozen), one with a NaN would put a NaN
// into the world. A refused sample is logged with its reason and changes nothing.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>

#include "lpss.h"

namespace lpss::dds {

/// How far ahead of the newest frame a reader knows has started a sample may be. For workers and the
/// coordinator, which know each frame's start: a faster worker's sample of the next frame can arrive
/// before that frame's start does.
inline constexpr std::uint64_t kFramesAhead = 2;
/// For clients, which learn frames from the workers' marks: marks travel on a topic of their own and were
/// seen arriving 3 frames after the samples of their frame (a late joiner refused those samples and never
/// showed a frame). Also for a worker joining a running world, which learns frames from starts that come
/// late (see Worker::State::frames_ahead). Ten seconds at 60 frames a second: a peer's sample further ahead
/// is still refused.
inline constexpr std::uint64_t kClientFramesAhead = 600;

/// Why `sample` cannot come from an lpss cluster whose newest started frame, as the reader knows it, is
/// `newest_frame`, at most `frames_ahead` ahead of it; empty when it can. Checks the sector key's range,
/// the frame, the lengths of the sequences against each other, and that every body's state is finite.
std::string implausible(const wire::SectorFrame& sample, std::uint64_t newest_frame,
                        std::uint64_t frames_ahead = kFramesAhead);

/// A reader's refusals: the first of each kind (its reason without numbers) is logged, then at most one a
/// second of that kind with the count so far, so that a flood of garbage costs a few log lines a second.
class RefusedSamples {
public:
    explicit RefusedSamples(std::string reader) : reader_(std::move(reader)) {}
    void refuse(const std::string& why);
    std::uint64_t count() const { return count_; }

private:
    std::string reader_;
    std::uint64_t count_ = 0;
    std::map<std::string, std::chrono::steady_clock::time_point> logged_;  ///< by kind
};

}  // namespace lpss::dds
