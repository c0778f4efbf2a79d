// libFuzzer target: a sequence of sector samples as a reader takes them off the wire from anyone on the
// domain: each decoded from CDR (as Fast DDS hands a payload to the type), checked by dds::implausible,
// ordered by SectorChain and applied to a SectorMirror, as lpss::Client does. The input is split into
// samples at each 0xFF 0xFE 0xFD 0xFC marker. No crash, no hang, no sanitizer finding, whatever the bytes.
#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <vector>

#include "lpss.h"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/sector_mirror.hpp"

namespace {

constexpr std::uint8_t kMarker[] = {0xFF, 0xFE, 0xFD, 0xFC};

/// Decodes one sample as Fast DDS would: refused when the bytes do not hold one.
bool decode(const std::uint8_t* data, std::size_t size, lpss::wire::SectorFrame& out) {
    std::vector<char> bytes(data, data + size);  // FastBuffer wants a writable buffer
    eprosima::fastcdr::FastBuffer buffer(bytes.data(), bytes.size());
    eprosima::fastcdr::Cdr cdr(buffer, eprosima::fastcdr::Cdr::DEFAULT_ENDIAN,
                               eprosima::fastcdr::Cdr::DDS_CDR);
    try {
        cdr.read_encapsulation();
        out.deserialize(cdr);
        return true;
    } catch (const eprosima::fastcdr::exception::Exception&) {
        return false;
    } catch (const std::bad_alloc&) {
        return false;  // a length that claims more than memory holds
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<lpss::wire::SectorFrame> samples;
    std::size_t start = 0;
    while (start <= size && samples.size() < 64) {
        std::size_t end = start;
        while (end + sizeof kMarker <= size && std::memcmp(data + end, kMarker, sizeof kMarker) != 0)
            ++end;
        if (end + sizeof kMarker > size) end = size;
        lpss::wire::SectorFrame sample;
        if (decode(data + start, end - start, sample)) samples.push_back(std::move(sample));
        start = end + sizeof kMarker;
    }
    lpss::dds::SectorChain chain;
    lpss::dds::SectorMirror mirror;
    std::uint64_t newest = 0;
    std::vector<const lpss::wire::SectorFrame*> batch;
    for (const lpss::wire::SectorFrame& sample : samples) {
        newest = std::max<std::uint64_t>(newest, sample.frame() > 2 ? sample.frame() - 2 : 0);
        if (!lpss::dds::implausible(sample, newest, lpss::dds::kClientFramesAhead).empty()) continue;
        if (chain.stale(sample) || !chain.accept(sample)) continue;
        batch.push_back(&sample);
    }
    std::vector<lpss::BodyId> left;
    mirror.apply(batch, &left);
    chain.forget_applied(newest);
    return 0;
}
