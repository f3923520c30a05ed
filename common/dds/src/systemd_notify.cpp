#include "causal/dds/systemd_notify.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace causal::dds {

namespace {
std::atomic<bool> reloading{false};
}  // namespace

NotifyResult notify_systemd_reloading() {
  reloading = true;
  return notify_systemd("RELOADING=1");
}

NotifyResult notify_systemd(const std::string& state) {
  if (reloading && state == "STOPPING=1") return NotifyResult::Sent;  // not stopping: reloading (see header)
  const char* name = std::getenv("NOTIFY_SOCKET");
  if (name == nullptr || name[0] == '\0') return NotifyResult::NoSocket;
  const std::size_t length = std::strlen(name);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if ((name[0] != '/' && name[0] != '@') || length >= sizeof(address.sun_path)) return NotifyResult::Failed;
  std::memcpy(address.sun_path, name, length);
  if (name[0] == '@') address.sun_path[0] = '\0';  // abstract namespace: the name's length counts, no terminator
  const auto address_length = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + length);
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return NotifyResult::Failed;
  const ssize_t sent = ::sendto(fd, state.data(), state.size(), MSG_NOSIGNAL,
                                reinterpret_cast<const sockaddr*>(&address), address_length);
  ::close(fd);
  return sent == static_cast<ssize_t>(state.size()) ? NotifyResult::Sent : NotifyResult::Failed;
}

}  // namespace causal::dds
