#include "udp_sender.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace lpss::dis {

Expected<UdpSender> UdpSender::open(const std::string& address, std::uint16_t port, bool broadcast,
                                    int multicast_ttl) {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    if (inet_pton(AF_INET, address.c_str(), &to.sin_addr) != 1)
        return Error{"--dis-address: '" + address + "' is not an IPv4 address"};
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return Error{std::string("cannot open a UDP socket: ") + std::strerror(errno)};
    UdpSender sender(fd);
    const int on = broadcast ? 1 : 0;
    if (::setsockopt(fd, SOL_SOCKET, SO_BROADCAST, &on, sizeof on) != 0)
        return Error{std::string("cannot allow broadcast: ") + std::strerror(errno)};
    const unsigned char ttl = static_cast<unsigned char>(multicast_ttl);
    if (::setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0)
        return Error{std::string("cannot set the multicast TTL: ") + std::strerror(errno)};
    // Connected: the kernel checks the route once, and a broadcast address without --broadcast is refused
    // here with EACCES rather than at every send.
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) != 0) {
        return Error{"cannot send to " + address + ":" + std::to_string(port) + ": " + std::strerror(errno) +
                     (errno == EACCES ? " (a broadcast address needs --broadcast)" : "")};
    }
    return sender;
}

UdpSender::UdpSender(UdpSender&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), errors_(other.errors_) {}

UdpSender& UdpSender::operator=(UdpSender&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = std::exchange(other.fd_, -1);
        errors_ = other.errors_;
    }
    return *this;
}

UdpSender::~UdpSender() {
    if (fd_ >= 0) ::close(fd_);
}

bool UdpSender::send(const std::uint8_t* data, std::size_t size) {
    // A connected UDP socket reports an earlier datagram's ICMP "port unreachable" (no receiver yet) on a
    // later send: not a fault of this datagram, so it is sent again once.
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (::send(fd_, data, size, 0) == static_cast<ssize_t>(size)) return true;
        if (errno != ECONNREFUSED) break;
    }
    ++errors_;
    return false;
}

}  // namespace lpss::dis
