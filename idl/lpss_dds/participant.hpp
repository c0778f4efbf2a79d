// Fast DDS entities for lpss programs, each owned by one RAII object: a participant (with its publisher,
// subscriber and topics), typed writers and readers, and an inbox that wakes a thread when any of its
// readers has data. Topic names and QoS live in topics.hpp.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "lpss/common/expected.hpp"

namespace lpss::dds {

namespace fdds = eprosima::fastdds::dds;

/// A generated type whose getKey is safe to call from several threads. fastddsgen's getKey serializes the
/// key into one buffer held by the type, and a participant's writer and reader of a topic share the type:
/// the writer computes the key of each sample it writes, the reader (on its receiving thread) that of each
/// sample that comes without a key hash. A key computed while the other thread filled the buffer put a
/// sample in a stray instance that is never written again (seen: a worker's sector writer holding two such
/// samples among its last 8192, and every heartbeat since carrying a GAP for each sequence number after
/// them, which readers take one by one: a drifting world slower by the minute).
template <class PubSub>
class LockedKeyType : public PubSub {
public:
    bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return PubSub::getKey(data, handle, force_md5);
    }

private:
    std::mutex mutex_;
};

/// One DDS participant on a domain, with the publisher, subscriber and topics its writers and readers use.
class Participant {
public:
    /// Joins `domain` with the profile in `profile_file`, or with lpss's built-in local profile (shared
    /// memory and loopback only) when it is empty. Refused with the reason when the profile is unreadable
    /// or the participant cannot be created. `avoid`: participant ids this process used before. Fast DDS
    /// 2.9 makes a participant's GUID from its process and its participant id, so a second participant of
    /// the same id in a process is, to peers that never heard the first one leave (a link cut), the first
    /// one, whose samples they have had: they drop what it writes (seen: a worker that joined again after a
    /// cut, its request to join never read).
    /// `security`: an identity folder (deploy/security/identities.sh) for DDS Security; none when empty.
    static Expected<std::unique_ptr<Participant>> create(int domain, const std::string& profile_file,
                                                         const std::string& name,
                                                         const std::set<int>& avoid = {},
                                                         const std::string& security = "");
    ~Participant();
    Participant(const Participant&) = delete;
    Participant& operator=(const Participant&) = delete;

    /// The topic `name` of type PubSub (registered on first use).
    template <class PubSub>
    fdds::Topic* topic(const std::string& name) {
        fdds::TypeSupport type(new LockedKeyType<PubSub>());
        return topic(name, type);
    }
    /// A content-filtered view of the sector frames topic holding only sectors with indices in
    /// [lo, hi] on each axis (sector_filters.hpp).
    fdds::TopicDescription* sector_region(const std::string& frames_topic, const std::int64_t lo[3],
                                          const std::int64_t hi[3]);
    /// A content-filtered view of the sector frames topic holding only the samples addressed to a worker
    /// (sector_filters.hpp).
    fdds::TopicDescription* sector_recipient(const std::string& frames_topic, std::uint32_t worker);

    fdds::DomainParticipant* raw() { return participant_; }
    fdds::Publisher* publisher() { return publisher_; }
    fdds::Subscriber* subscriber() { return subscriber_; }
    /// For sector samples only (own_partition.hpp): the publisher of this participant's own, in the default
    /// partition and its own; the subscriber of every other sector writer's, not of its own.
    fdds::Publisher* sector_publisher() { return sector_publisher_; }
    fdds::Subscriber* sector_subscriber() { return sector_subscriber_; }
    int domain() const { return domain_; }
    /// Its participant id (which ports it listens on); -1 if Fast DDS chose it.
    int participant_id() const { return participant_id_; }

private:
    Participant() = default;
    fdds::Topic* topic(const std::string& name, fdds::TypeSupport& type);

    int domain_ = 0;
    int participant_id_ = -1;
    fdds::DomainParticipant* participant_ = nullptr;
    fdds::Publisher* publisher_ = nullptr;
    fdds::Subscriber* subscriber_ = nullptr;
    fdds::Publisher* sector_publisher_ = nullptr;
    fdds::Subscriber* sector_subscriber_ = nullptr;
    std::map<std::string, fdds::Topic*> topics_;
    std::map<std::string, fdds::TopicDescription*> filtered_;
    std::unique_ptr<fdds::IContentFilterFactory> filter_factory_;
    fdds::TopicDescription* filtered(const std::string& frames_topic, const char* filter_class,
                                     const std::vector<std::string>& parameters);
    int next_filter_ = 0;
};

/// Asserts a writer's liveliness every `period` from a thread of its own, for as long as it exists: a
/// writer with a lease (topics.hpp) stays alive to its readers while the process runs and reaches them,
/// whatever its main thread is doing (building a large world takes seconds).
class LivelinessBeat {
public:
    LivelinessBeat(fdds::DataWriter* writer, std::chrono::milliseconds period);
    ~LivelinessBeat();
    LivelinessBeat(const LivelinessBeat&) = delete;
    LivelinessBeat& operator=(const LivelinessBeat&) = delete;

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
    std::thread thread_;
};

/// Wakes a waiting thread when any reader attached to it has data.
class Inbox : public fdds::DataReaderListener {
public:
    void on_data_available(fdds::DataReader*) override;
    void on_subscription_matched(fdds::DataReader*, const fdds::SubscriptionMatchedStatus& status) override;
    void on_liveliness_changed(fdds::DataReader*, const fdds::LivelinessChangedStatus& status) override;
    /// Waits until data arrived since the last call, or the timeout passed. True when data arrived.
    bool wait(std::chrono::milliseconds timeout);
    /// Wakes the waiting thread without data (to stop it).
    void poke();
    int matched_writers() const { return matched_.load(); }
    /// A writer's liveliness changed (readers that ask for a lease: topics.hpp): it is alive (new, or again),
    /// or it stopped asserting it or went away. By publication handle (SampleInfo::publication_handle).
    struct Liveliness {
        fdds::InstanceHandle_t writer;
        bool alive = false;
        /// The reader's writers alive after this change. Fast DDS 2.9 adds up the changes of two writers
        /// whose liveliness changes on two threads at once and names only the last writer
        /// (DataReaderImpl::update_liveliness_status): a reader that has one leased topic can trust the count
        /// where a writer's own report went missing.
        std::int32_t alive_count = 0;
        /// More than one writer's change in this report: `writer` and `alive` tell of the last one only.
        bool merged = false;
    };
    /// The changes since the last call, in order.
    std::vector<Liveliness> take_liveliness();

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    bool pending_ = false;
    std::vector<Liveliness> liveliness_;
    std::atomic<int> matched_{0};
};

/// An endpoint's GUID as 16 bytes (participant prefix, entity id): how lpss names a reader on the wire.
using GuidBytes = std::array<std::uint8_t, 16>;
inline GuidBytes guid_bytes(const eprosima::fastrtps::rtps::GUID_t& guid) {
    GuidBytes out{};
    std::copy(std::begin(guid.guidPrefix.value), std::end(guid.guidPrefix.value), out.begin());
    std::copy(std::begin(guid.entityId.value), std::end(guid.entityId.value), out.begin() + 12);
    return out;
}
inline GuidBytes guid_bytes(const fdds::InstanceHandle_t& handle) {
    eprosima::fastrtps::rtps::GUID_t guid;
    eprosima::fastrtps::rtps::iHandle2GUID(guid, handle);
    return guid_bytes(guid);
}

/// The participant an endpoint belongs to: the first 12 bytes of its GUID (its prefix).
using ParticipantPrefix = std::array<std::uint8_t, 12>;
inline ParticipantPrefix participant_of(const fdds::InstanceHandle_t& handle) {
    const GuidBytes guid = guid_bytes(handle);
    ParticipantPrefix out{};
    std::copy(guid.begin(), guid.begin() + 12, out.begin());
    return out;
}

/// A typed data writer; counts the readers it has matched.
template <class T>
class Writer : public fdds::DataWriterListener {
public:
    Writer(Participant& participant, fdds::Topic* topic, const fdds::DataWriterQos& qos)
        : Writer(participant.publisher(), topic, qos) {}
    /// On a publisher of the participant's other than its default one (Participant::sector_publisher).
    Writer(fdds::Publisher* publisher, fdds::Topic* topic, const fdds::DataWriterQos& qos)
        : publisher_(publisher),
          writer_(publisher->create_datawriter(topic, qos, this, fdds::StatusMask::publication_matched())) {}
    ~Writer() override {
        if (writer_) publisher_->delete_datawriter(writer_);
    }
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    bool ok() const { return writer_ != nullptr; }
    bool write(const T& sample) { return writer_->write(const_cast<T*>(&sample)); }
    bool dispose(const T& sample) {
        return writer_->dispose(const_cast<T*>(&sample), fdds::HANDLE_NIL) ==
               eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
    }
    int matched() const { return matched_.load(); }
    /// Whether every matched reader acknowledged what was written, within `limit`: what a writer that is
    /// about to go must wait for (reliable delivery ends with its participant).
    bool delivered(std::chrono::milliseconds limit) {
        return writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(limit.count() / 1000.0)) ==
               eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
    }
    /// Readers matched since the last call (a late joiner to serve).
    int take_new_matches() { return new_matches_.exchange(0); }
    /// Whether this writer has matched the reader with this GUID (see guid_bytes): what it writes now
    /// reaches that reader. A reader matching a writer says nothing of the writer's side, which discovery
    /// can complete seconds later.
    bool reaches(const GuidBytes& reader) const {
        std::lock_guard<std::mutex> lock(readers_mutex_);
        return matched_readers_.count(reader) > 0;
    }
    void on_publication_matched(fdds::DataWriter*, const fdds::PublicationMatchedStatus& status) override {
        {
            std::lock_guard<std::mutex> lock(readers_mutex_);
            const GuidBytes reader = guid_bytes(status.last_subscription_handle);
            if (status.current_count_change > 0) matched_readers_.insert(reader);
            if (status.current_count_change < 0) matched_readers_.erase(reader);
        }
        matched_.store(status.current_count);
        if (status.current_count_change > 0) new_matches_.fetch_add(status.current_count_change);
    }
    fdds::DataWriter* raw() { return writer_; }

private:
    // The counters come before the writer: its listener may be called while it is being created (a reader
    // known already), and a counter initialized after it would lose that match (seen: a client's commands
    // writer that never counted the coordinator's reader).
    std::atomic<int> matched_{0};
    std::atomic<int> new_matches_{0};
    mutable std::mutex readers_mutex_;
    std::set<GuidBytes> matched_readers_;
    fdds::Publisher* publisher_;
    fdds::DataWriter* writer_;
};

/// What a reader tells its inbox of.
enum class Wake {
    on_data,  ///< every sample that comes, matches and liveliness
    /// Matches and liveliness only: for samples a loop takes whenever something else woke it. Each wake is
    /// a futex call on both sides and a context switch (docs/protocol.md, "A standby coordinator").
    on_news,
};

/// A typed data reader that reports to an inbox (or to a listener that tells one).
template <class T>
class Reader {
public:
    Reader(Participant& participant, fdds::TopicDescription* topic, const fdds::DataReaderQos& qos,
           fdds::DataReaderListener* inbox, Wake wake = Wake::on_data)
        : Reader(participant.subscriber(), topic, qos, inbox, wake) {}
    /// On a subscriber of the participant's other than its default one (Participant::sector_subscriber).
    Reader(fdds::Subscriber* subscriber, fdds::TopicDescription* topic, const fdds::DataReaderQos& qos,
           fdds::DataReaderListener* inbox, Wake wake = Wake::on_data)
        : subscriber_(subscriber),
          inbox_(inbox),
          reader_(subscriber->create_datareader(topic, qos, inbox, status_mask(inbox, wake))) {}
    ~Reader() {
        if (reader_) subscriber_->delete_datareader(reader_);
    }
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;

    bool ok() const { return reader_ != nullptr; }
    /// Takes the samples available when called (at most `at_most` of them) and calls each(sample, info) for
    /// each (a disposed instance is passed with info.valid_data false); each may move the sample away.
    /// Returns how many were taken. Those that arrive meanwhile wait for the next call: a reader slower than
    /// its writers would otherwise never return (seen: a client that joined a drifting world taking sector
    /// samples for minutes, its marks never read).
    template <class F>
    int take_all(F&& each, std::uint64_t at_most = ~std::uint64_t{0}) {
        int count = 0;
        T sample;
        fdds::SampleInfo info;
        for (std::uint64_t left = std::min(std::max<std::uint64_t>(reader_->get_unread_count(), 1), at_most);
             left > 0; --left) {
            if (reader_->take_next_sample(&sample, &info) !=
                eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
                break;
            each(sample, info);
            ++count;
        }
        return count;
    }
    /// This reader's GUID, as writers' reaches() take it.
    GuidBytes guid() const { return guid_bytes(reader_->guid()); }
    /// Writers matched now.
    int matched() const {
        fdds::SubscriptionMatchedStatus status;
        reader_->get_subscription_matched_status(status);
        return status.current_count;
    }
    /// What it tells its inbox of from now on. (Fast DDS 2.9 sets the mask without a lock: a sample its
    /// receiving thread delivers at that moment may be told of under the old one, a wake more or less.)
    void wake(Wake wake) { reader_->set_listener(inbox_, status_mask(inbox_, wake)); }
    /// Samples received and not taken yet.
    std::uint64_t unread() const { return reader_->get_unread_count(); }
    fdds::DataReader* raw() { return reader_; }

private:
    static fdds::StatusMask status_mask(const fdds::DataReaderListener* inbox, Wake wake) {
        if (inbox == nullptr) return fdds::StatusMask::none();
        fdds::StatusMask news = fdds::StatusMask::subscription_matched()
                                << fdds::StatusMask::liveliness_changed();
        return wake == Wake::on_data ? news << fdds::StatusMask::data_available() : news;
    }

    fdds::Subscriber* subscriber_;
    fdds::DataReaderListener* inbox_;
    fdds::DataReader* reader_;
};

}  // namespace lpss::dds
