// A UDP socket that sends datagrams to one address (RAII). DIS runs over UDP; lpss-dis sends to
// 127.0.0.1 unless told otherwise, and to a broadcast or multicast address only when asked.
#pragma once

#include <cstdint>
#include <string>

#include "lpss/common/expected.hpp"

namespace lpss::dis {

class UdpSender {
public:
    /// `address` is an IPv4 address; a broadcast address needs `broadcast`; a multicast one is sent with
    /// `multicast_ttl` hops (1: this link only).
    static Expected<UdpSender> open(const std::string& address, std::uint16_t port, bool broadcast,
                                    int multicast_ttl);
    UdpSender(UdpSender&& other) noexcept;
    UdpSender& operator=(UdpSender&& other) noexcept;
    UdpSender(const UdpSender&) = delete;
    UdpSender& operator=(const UdpSender&) = delete;
    ~UdpSender();

    /// False if the datagram was not sent (the error is counted, not fatal: DIS is best-effort).
    bool send(const std::uint8_t* data, std::size_t size);
    std::uint64_t errors() const { return errors_; }

private:
    explicit UdpSender(int fd) : fd_(fd) {}
    int fd_ = -1;
    std::uint64_t errors_ = 0;
};

}  // namespace lpss::dis
