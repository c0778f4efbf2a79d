#include "lpss_dds/participant.hpp"

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <spdlog/spdlog.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <fastdds/dds/topic/ContentFilteredTopic.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fastdds/rtps/common/Locator.h>
#include <fastrtps/utils/IPLocator.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <set>
#include <utility>

#include "lpss_dds/own_partition.hpp"
#include "lpss_dds/sector_filters.hpp"
#include "lpss_dds/security.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss::dds {

extern const char* const kDefaultProfileXml;

namespace {

using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;

/// Fast DDS keeps profiles in a process-wide factory: load lpss's (or the user's) once.
Expected<fdds::DomainParticipantQos> participant_qos(const std::string& profile_file) {
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    static std::string loaded;
    static bool loaded_ok = false;
    const std::string wanted = profile_file.empty() ? std::string("<built-in>") : profile_file;
    if (!loaded_ok || loaded != wanted) {
        // Fast DDS's own default files (FASTRTPS_DEFAULT_PROFILES_FILE) first, so that they cannot take
        // over later: load_profiles() runs once, also inside create_participant.
        factory->load_profiles();
        ReturnCode rc;
        if (profile_file.empty()) {
            rc = factory->load_XML_profiles_string(kDefaultProfileXml, std::strlen(kDefaultProfileXml));
        } else {
            if (!std::ifstream(profile_file)) return Error{"cannot read the DDS profile " + profile_file};
            rc = factory->load_XML_profiles_file(profile_file);
        }
        if (rc != ReturnCode::RETCODE_OK) {
            return Error{"the DDS profile " + wanted + " could not be loaded (is it Fast DDS profile XML?)"};
        }
        loaded = wanted;
        loaded_ok = true;
    }
    // Loading a profile does not change the factory's default QoS: setting the default to
    // PARTICIPANT_QOS_DEFAULT makes it the profile marked is_default_profile="true" (without this, every
    // lpss participant ran with Fast DDS's defaults, multicast discovery on every interface included).
    factory->set_default_participant_qos(fdds::PARTICIPANT_QOS_DEFAULT);
    fdds::DomainParticipantQos qos;
    factory->get_default_participant_qos(qos);
    return qos;
}

/// LPSS_DDS_LOG=warning (or info) lets Fast DDS's own messages through to the process's output: its
/// transports say there what they drop or time out on, which nothing else reports. Fast DDS's log is
/// process-wide, so this is read once.
void apply_dds_log_verbosity() {
    static const bool applied = [] {
        const char* wanted = std::getenv("LPSS_DDS_LOG");
        if (wanted == nullptr) return true;
        using Log = eprosima::fastdds::dds::Log;
        if (std::strcmp(wanted, "warning") == 0)
            Log::SetVerbosity(Log::Warning);
        else if (std::strcmp(wanted, "info") == 0)
            Log::SetVerbosity(Log::Info);
        else if (std::strcmp(wanted, "error") == 0)
            Log::SetVerbosity(Log::Error);
        else
            spdlog::warn("LPSS_DDS_LOG={} is not one of error, warning, info: ignored", wanted);
        return true;
    }();
    (void)applied;
}

/// Creates a participant under the id lpss chooses when the profile leaves it to Fast DDS: one with fresh
/// shared-memory ports (shm_cleanup.hpp) when the profile uses shared memory, or else the lowest not in
/// `avoid` (participant.hpp says why), or Fast DDS's own choice when `avoid` is empty or that id is refused.
/// Sets `id` to the one taken (-1: Fast DDS chose). Null if Fast DDS creates none.
fdds::DomainParticipant* create_under_chosen_id(int domain, fdds::DomainParticipantQos qos,
                                                bool shared_memory, const std::set<int>& avoid, int& id) {
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    std::optional<int> chosen;
    if (qos.wire_protocol().participant_id < 0 && shared_memory) {
        chosen = participant_id_with_fresh_ports(domain, avoid);
    } else if (qos.wire_protocol().participant_id < 0 && !avoid.empty()) {
        for (chosen = 0; avoid.count(*chosen);)
            ++*chosen;
    }
    if (chosen) {
        fdds::DomainParticipantQos with_id = qos;
        with_id.wire_protocol().participant_id = *chosen;
        if (fdds::DomainParticipant* p = factory->create_participant(domain, with_id)) {
            id = *chosen;
            return p;
        }
    }
    id = qos.wire_protocol().participant_id;
    return factory->create_participant(domain, qos);
}

/// Makes every peer on `domain` announce itself again, now that a participant just created there listens.
/// Fast DDS 2.9 sends a participant's first announcement before it listens (RTPSParticipantImpl::enable
/// enables the built-in protocols, then registers the receivers), and a peer answers a participant new to
/// it only once, at once: an answer that comes back within that gap is dropped, and the newcomer learns of
/// that peer only from the peer's periodic announcement (every second in lpss's profile). Measured on
/// this 2-core machine against a 4-participant domain: 9 of 12 newcomers missed at least one peer's
/// answer and waited 0.14-0.89 s for it; a joining client matched a running cluster in 0.03-1.1 s. A peer
/// answers any participant new to it, and answers to all it knows: a second participant created and
/// deleted at once is new to every peer, and the first one hears their answers. With it, 16 of 16
/// newcomers found all four peers within 19 ms (docs/operations.md, "Late joiners").
/// LPSS_DDS_DISCOVERY_PROMPT=0 turns it off (to measure it). Not done for a secured participant: the
/// prompt would start an authentication handshake with every peer that it abandons at once.
void prompt_peers_to_announce(int domain, fdds::DomainParticipantQos qos, bool shared_memory,
                              std::set<int> avoid, int main_id) {
    const char* wanted = std::getenv("LPSS_DDS_DISCOVERY_PROMPT");
    if (wanted != nullptr && std::strcmp(wanted, "0") == 0) return;
    qos.name(qos.name().to_string() + "-discovery-prompt");
    // Its own id, chosen as the first participant's was, and not that one's.
    qos.wire_protocol().participant_id = -1;
    if (main_id >= 0 && (shared_memory || !avoid.empty())) avoid.insert(main_id);
    int id = -1;
    fdds::DomainParticipant* prompt = create_under_chosen_id(domain, qos, shared_memory, avoid, id);
    // Deleted at once: its announcement is out, and its departure follows it on the same path, so a peer
    // reads the announcement (and answers to all) before it reads that the prompt is gone.
    if (prompt != nullptr) fdds::DomainParticipantFactory::get_instance()->delete_participant(prompt);
}

}  // namespace

Expected<std::unique_ptr<Participant>> Participant::create(int domain, const std::string& profile_file,
                                                           const std::string& name,
                                                           const std::set<int>& avoid,
                                                           const std::string& security) {
    if (domain < 0 || domain > 232)
        return Error{"DDS domain id must be between 0 and 232, got " + std::to_string(domain)};
    apply_dds_log_verbosity();
    Expected<fdds::DomainParticipantQos> qos = participant_qos(profile_file);
    if (!qos) return qos.error();
    qos->name(name);
    if (!security.empty()) {
        if (Status st = apply_security(*qos, security); !st) return st.error();
    }
    std::unique_ptr<Participant> p(new Participant());
    p->domain_ = domain;
    // Shared-memory ports no process has used since they were last cleaned (see shm_cleanup.hpp), unless
    // the profile chose an id or uses no shared memory.
    bool shared_memory = qos->transport().use_builtin_transports;
    for (const auto& transport : qos->transport().user_transports)
        shared_memory =
            shared_memory ||
            std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(transport);
    p->participant_ = create_under_chosen_id(domain, qos.value(), shared_memory, avoid, p->participant_id_);
    if (p->participant_ == nullptr) {
        return Error{"cannot create a DDS participant on domain " + std::to_string(domain) +
                     (security.empty()
                          ? std::string()
                          : " with the identity in " + security +
                                " (Fast DDS refused it: an expired or revoked certificate, or "
                                "signatures not from its CAs? LPSS_DDS_SECURITY_LOG=FILE says more)")};
    }
    if (security.empty())
        prompt_peers_to_announce(domain, qos.value(), shared_memory, avoid, p->participant_id_);
    p->publisher_ = p->participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    p->subscriber_ = p->participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    ParticipantPrefix prefix{};
    const auto& guid_prefix = p->participant_->guid().guidPrefix.value;
    std::copy(std::begin(guid_prefix), std::end(guid_prefix), prefix.begin());
    const std::string own = own_partition(prefix);
    fdds::PublisherQos own_samples = fdds::PUBLISHER_QOS_DEFAULT;
    own_samples.partition().push_back("");  // every reader in the default partition: clients, other vendors
    own_samples.partition().push_back(own.c_str());
    p->sector_publisher_ = p->participant_->create_publisher(own_samples);
    fdds::SubscriberQos others_samples = fdds::SUBSCRIBER_QOS_DEFAULT;
    for (const std::string& pattern : every_own_partition_but(own))
        others_samples.partition().push_back(pattern.c_str());
    p->sector_subscriber_ = p->participant_->create_subscriber(others_samples);
    p->filter_factory_ = std::make_unique<SectorFilterFactory>();
    p->participant_->register_content_filter_factory(kRegionFilterClass, p->filter_factory_.get());
    p->participant_->register_content_filter_factory(kRecipientFilterClass, p->filter_factory_.get());
    if (p->publisher_ == nullptr || p->subscriber_ == nullptr || p->sector_publisher_ == nullptr ||
        p->sector_subscriber_ == nullptr)
        return Error{"cannot create DDS publisher/subscriber"};
    return p;
}

Participant::~Participant() {
    if (participant_ == nullptr) return;
    // Readers and writers belong to their RAII owners, which must be gone by now; what is left here is
    // ours: filtered topics, topics, publisher, subscriber, then the participant itself.
    for (auto& [name, topic] : filtered_) {
        participant_->delete_contentfilteredtopic(static_cast<fdds::ContentFilteredTopic*>(topic));
    }
    for (auto& [name, topic] : topics_)
        participant_->delete_topic(topic);
    if (publisher_) participant_->delete_publisher(publisher_);
    if (subscriber_) participant_->delete_subscriber(subscriber_);
    if (sector_publisher_) participant_->delete_publisher(sector_publisher_);
    if (sector_subscriber_) participant_->delete_subscriber(sector_subscriber_);
    participant_->unregister_content_filter_factory(kRegionFilterClass);
    participant_->unregister_content_filter_factory(kRecipientFilterClass);
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

fdds::Topic* Participant::topic(const std::string& name, fdds::TypeSupport& type) {
    auto it = topics_.find(name);
    if (it != topics_.end()) return it->second;
    type.register_type(participant_);
    fdds::Topic* topic = participant_->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    topics_.emplace(name, topic);
    return topic;
}

fdds::TopicDescription* Participant::filtered(const std::string& frames_topic, const char* filter_class,
                                              const std::vector<std::string>& parameters) {
    auto it = topics_.find(frames_topic);
    if (it == topics_.end()) return nullptr;
    const std::string name = frames_topic + "/filtered" + std::to_string(next_filter_++);
    // The expression is not read by lpss's filters, but must not be empty: Fast DDS announces a filter
    // to the writers (which then filter for this reader) only when it has one.
    fdds::ContentFilteredTopic* topic =
        participant_->create_contentfilteredtopic(name, it->second, filter_class, parameters, filter_class);
    if (topic) filtered_.emplace(name, topic);
    return topic;
}

fdds::TopicDescription* Participant::sector_region(const std::string& frames_topic, const std::int64_t lo[3],
                                                   const std::int64_t hi[3]) {
    std::vector<std::string> parameters;
    for (int a = 0; a < 3; ++a) {
        parameters.push_back(std::to_string(lo[a]));
        parameters.push_back(std::to_string(hi[a]));
    }
    return filtered(frames_topic, kRegionFilterClass, parameters);
}

fdds::TopicDescription* Participant::sector_recipient(const std::string& frames_topic, std::uint32_t worker) {
    return filtered(frames_topic, kRecipientFilterClass, {std::to_string(worker)});
}

LivelinessBeat::LivelinessBeat(fdds::DataWriter* writer, std::chrono::milliseconds period)
    : thread_([this, writer, period] {
          std::unique_lock<std::mutex> lock(mutex_);
          while (!stop_) {
              writer->assert_liveliness();
              cv_.wait_for(lock, period, [this] { return stop_; });
          }
      }) {}

LivelinessBeat::~LivelinessBeat() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
}

void Inbox::on_data_available(fdds::DataReader*) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        pending_ = true;
    }
    cv_.notify_all();
}

void Inbox::on_liveliness_changed(fdds::DataReader*, const fdds::LivelinessChangedStatus& status) {
    if (status.not_alive_count_change == 0 && status.alive_count_change == 0) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        // Alive only if a writer became alive (new, or back from a lapse). A writer that goes away (its
        // process ended, or it was unmatched after its lapse) lowers alive_count or not_alive_count without
        // raising the other: gone, not back. Read as back, a standby that came back from a pause and then
        // exited was waited for by its coordinator until every worker was taken as gone.
        // What one writer's change can be: new or gone (alive or not), lapsed, back from a lapse.
        const int a = status.alive_count_change, n = status.not_alive_count_change;
        const bool one_writer =
            (a == 0 && n == -1) || (n == 0 && (a == 1 || a == -1)) || (a == -n && (a == 1 || a == -1));
        liveliness_.push_back({status.last_publication_handle, a > 0, status.alive_count, !one_writer});
    }
    on_data_available(nullptr);
}

std::vector<Inbox::Liveliness> Inbox::take_liveliness() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::exchange(liveliness_, {});
}

void Inbox::on_subscription_matched(fdds::DataReader*, const fdds::SubscriptionMatchedStatus& status) {
    matched_.fetch_add(status.current_count_change);
    on_data_available(nullptr);
}

bool Inbox::wait(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    const bool got = cv_.wait_for(lock, timeout, [this] { return pending_; });
    pending_ = false;
    return got;
}

void Inbox::poke() { on_data_available(nullptr); }

// ---- QoS

namespace {

// Writers and readers take the same settings; their QoS types differ but share these members.
template <class Qos>
Qos with_delivery(Qos q, const Delivery& d) {
    // Fast DDS defaults to 10 instances per endpoint: a world has a sample per sector and per body.
    q.resource_limits().max_instances = 0;                   // 0: unlimited
    q.resource_limits().max_samples = 0;                     // 0: unlimited
    q.resource_limits().max_samples_per_instance = d.depth;  // 0 would mean one
    q.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    if (d.lease_ms > 0) {
        // Asserted writer by writer (LivelinessBeat). Not AUTOMATIC or MANUAL_BY_PARTICIPANT: a Fast DDS 2.9
        // reader takes word from any writer of those kinds as word from all of them
        // (LivelinessManager::assert_liveliness), so a killed worker stayed alive while the others wrote.
        q.liveliness().kind = fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS;
        q.liveliness().lease_duration = eprosima::fastrtps::Duration_t(d.lease_ms / 1000.0);
    }
    q.durability().kind = d.durable ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
    q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    q.history().depth = d.depth;
    // Samples are as large as their sector: each payload is allocated at its size and freed when no sample
    // needs it, so that memory follows what the histories hold now (a preallocating pool keeps the most
    // it ever held: the whole world, for a reader of the first frame's samples). Fast DDS 2.9 loses the
    // disposal of an instance under that policy (a removed plane stayed in every client: tested), so topics
    // with disposals keep a pool; their samples are small.
    q.endpoint().history_memory_policy = d.disposes
                                             ? eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE
                                             : eprosima::fastrtps::rtps::DYNAMIC_RESERVE_MEMORY_MODE;
    return q;
}

}  // namespace

fdds::DataWriterQos writer_qos(const Delivery& d) {
    fdds::DataWriterQos q = with_delivery(fdds::DATAWRITER_QOS_DEFAULT, d);
    // The writer's alone: a reader's lifespan is its own QoS in Fast DDS 2.9, so readers drop nothing they
    // have not taken.
    if (d.lifespan_ms > 0) q.lifespan().duration = eprosima::fastrtps::Duration_t(d.lifespan_ms / 1000.0);
    // Readers filter for themselves (workers' recipient filters, clients' regions), not the writers: Fast
    // DDS 2.9 does not leave room for the filter's inline QoS when it cuts a large sample into fragments
    // (RTPSWriter::calculateMaxDataSize: "inlineqos in future"), so a filtered sample over ~64 KB is never
    // sent ("Cannot add RTPS submessage ... Buffer too small", seen with a sector of 450 bodies). Over
    // shared memory a sample is written once for every reader anyway; a reader that does not want it reads
    // its first few dozen bytes.
    q.writer_resource_limits().reader_filters_allocation =
        eprosima::fastrtps::ResourceLimitedContainerConfig(0u, 0u, 0u);
    // A sample a reader lost (a shared-memory port full while it was busy) is repaired only once the writer
    // says what it has sent, on its heartbeat: every 3 s by default, and every frame waits for the marks
    // and samples of the frame before (seen: frames starting 2.9 s late in a drifting world). A heartbeat
    // every 100 ms bounds such a stall to about that, for a few dozen small messages a second per reader.
    q.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 100'000'000u);
    return q;
}

fdds::DataReaderQos reader_qos(const Delivery& d) { return with_delivery(fdds::DATAREADER_QOS_DEFAULT, d); }

fdds::DataReaderQos reader_qos_on_own_port(const Delivery& d) {
    fdds::DataReaderQos q = reader_qos(d);
    // A port the system has free now, asked for on every address; Fast DDS binds it again at once (the
    // window in which another process could take it is that short). Address 0.0.0.0: Fast DDS lists the
    // interfaces its transport's whitelist allows (only 127.0.0.1 with the built-in profile).
    const int probe = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (probe < 0) return q;
    sockaddr_in any{};
    any.sin_family = AF_INET;
    any.sin_addr.s_addr = htonl(INADDR_ANY);
    any.sin_port = 0;
    socklen_t length = sizeof(any);
    const bool bound = ::bind(probe, reinterpret_cast<sockaddr*>(&any), sizeof(any)) == 0 &&
                       ::getsockname(probe, reinterpret_cast<sockaddr*>(&any), &length) == 0;
    ::close(probe);
    if (!bound) return q;  // the participant's port, as any reader
    eprosima::fastrtps::rtps::Locator_t own;
    own.kind = LOCATOR_KIND_UDPv4;
    eprosima::fastrtps::rtps::IPLocator::setIPv4(own, 0, 0, 0, 0);
    own.port = ntohs(any.sin_port);
    q.endpoint().unicast_locator_list.push_back(own);
    return q;
}

}  // namespace lpss::dds
