#include "start_acknowledger.hpp"

#include <algorithm>

namespace lpss::coordinator {

wire::FrameAck frame_ack(std::uint32_t self, std::uint32_t term, std::uint64_t frame) {
    wire::FrameAck ack;
    ack.coordinator(self);
    ack.term(term);
    ack.frame(frame);
    return ack;
}

void StartAcknowledger::start_taking(std::uint32_t self, dds::fdds::DataReader* reader,
                                     dds::Writer<wire::FrameAck>* acks) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        self_ = self;
        acks_ = acks;
    }
    take_from(reader);  // what came before
}

void StartAcknowledger::stop_taking() {
    std::lock_guard<std::mutex> lock(mutex_);
    acks_ = nullptr;
}

bool StartAcknowledger::acknowledged(std::uint32_t term, std::uint64_t frame) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return term == acked_term_ && frame <= acked_frame_ && acked_frame_ != 0;
}

void StartAcknowledger::note_acknowledged(std::uint32_t term, std::uint64_t frame) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (term != acked_term_) {
        acked_term_ = term;
        acked_frame_ = frame;
    } else {
        acked_frame_ = std::max(acked_frame_, frame);
    }
}

void StartAcknowledger::on_data_available(dds::fdds::DataReader* reader) {
    bool taking = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        taking = acks_ != nullptr;
    }
    if (taking) take_from(reader);
    inbox_.on_data_available(reader);
}

void StartAcknowledger::take_from(dds::fdds::DataReader* reader) {
    // The reader's lock and mutex_ are never held the other way round: Fast DDS may call on_data_available
    // with the reader locked, so the sample is taken before mutex_ is, and mutex_ is not held while taking.
    for (;;) {
        wire::FrameGo go;
        dds::fdds::SampleInfo info;
        if (reader->take_next_sample(&go, &info) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
            return;
        std::lock_guard<std::mutex> lock(mutex_);
        // Frame 1 waits for the world's first state, a new term for the loop to follow it: never on sight
        // (before frame 1 the only acknowledgement is the hello, of term 0, and a start's term is 1 or more).
        const bool on_sight = acks_ != nullptr && info.valid_data && go.coordinator() != self_ &&
                              go.standby() == self_ && go.term() == acked_term_ &&
                              go.frame() == acked_frame_ + 1;
        if (on_sight) {
            acks_->write(frame_ack(self_, go.term(), go.frame()));
            acked_frame_ = go.frame();
        }
        arrived_.emplace_back(std::move(go), info);
    }
}

}  // namespace lpss::coordinator
