// A standby's reader of the coordinator's frame starts, and its quick answer to them. Every frame waits for
// the standby's acknowledgement of its start before any worker steps it. Written from the standby's follow
// loop, that acknowledgement waited for the loop's thread to wake and to finish what it was at (sector
// samples, 16 at a time): 0.3-0.4 ms from the start's writing to the acknowledgement's at the mean, measured
// on 10,000 resting bodies and 1,000 balls on one worker, where the start reached the worker itself in 0.27.
// So the starts are taken as they arrive, on Fast DDS's receiving thread, and those that may be acknowledged
// on sight are acknowledged there: named for this standby, of the term followed, the frame after the one
// last acknowledged under it. The follow loop still takes every start in order and acknowledges the others
// itself (frame 1, once the world's first state is whole; the first of a new term).
#pragma once

#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "lpss.h"
#include "lpss_dds/participant.hpp"

namespace lpss::coordinator {

/// A standby's acknowledgement of frame `frame`'s start under `term`, as coordinator `self` writes it.
wire::FrameAck frame_ack(std::uint32_t self, std::uint32_t term, std::uint64_t frame);

class StartAcknowledger : public dds::fdds::DataReaderListener {
public:
    /// `inbox`: where the follow loop waits, told of every start and of the reader's other news (matches,
    /// liveliness) as if it were the reader's listener.
    explicit StartAcknowledger(dds::Inbox& inbox) : inbox_(inbox) {}

    /// From now on (until stop_taking), the starts `reader` gets are taken as they come (those already
    /// there too), and those it may are acknowledged through `acks` as coordinator `self`; before, and
    /// after, they stay in the reader.
    void start_taking(std::uint32_t self, dds::fdds::DataReader* reader, dds::Writer<wire::FrameAck>* acks);
    void stop_taking();
    /// Whether `frame` was acknowledged under `term` (here or by note_acknowledged).
    bool acknowledged(std::uint32_t term, std::uint64_t frame) const;
    /// The follow loop acknowledged `frame` under `term`: the next frame of that term may be acknowledged
    /// here on sight.
    void note_acknowledged(std::uint32_t term, std::uint64_t frame);

    /// The starts taken since the last call, in the order they came, with their sample infos.
    template <class F>
    void take_all(F&& each) {
        std::vector<std::pair<wire::FrameGo, dds::fdds::SampleInfo>> taken;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            taken.swap(arrived_);
        }
        for (const auto& [go, info] : taken)
            each(go, info);
    }

    void on_data_available(dds::fdds::DataReader* reader) override;
    void on_subscription_matched(dds::fdds::DataReader* reader,
                                 const dds::fdds::SubscriptionMatchedStatus& status) override {
        inbox_.on_subscription_matched(reader, status);
    }
    void on_liveliness_changed(dds::fdds::DataReader* reader,
                               const dds::fdds::LivelinessChangedStatus& status) override {
        inbox_.on_liveliness_changed(reader, status);
    }

private:
    /// Takes what `reader` holds, acknowledging what it may.
    void take_from(dds::fdds::DataReader* reader);

    dds::Inbox& inbox_;
    mutable std::mutex mutex_;
    std::uint32_t self_ = 0;
    dds::Writer<wire::FrameAck>* acks_ = nullptr;  ///< while taking
    std::uint32_t acked_term_ = 0;
    std::uint64_t acked_frame_ = 0;  ///< the latest acknowledged under acked_term_
    std::vector<std::pair<wire::FrameGo, dds::fdds::SampleInfo>> arrived_;
};

}  // namespace lpss::coordinator
