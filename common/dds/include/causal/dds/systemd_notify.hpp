// Service state for systemd (units with Type=notify, deploy/systemd): READY=1 once the service's DDS entities
// exist and its run loop starts, STOPPING=1 when the loop ends, so `systemctl start` returns when the service
// can take data and units ordered After= it start only then.
//
// The sd_notify protocol is one datagram to the AF_UNIX socket named by $NOTIFY_SOCKET (a leading '@' names
// the abstract namespace); it is written here directly, so libsystemd is not needed. Outside systemd
// ($NOTIFY_SOCKET unset) nothing is sent.
#pragma once

#include <string>

namespace causal::dds {

enum class NotifyResult { Sent, NoSocket, Failed };

// Sends `state` (e.g. "READY=1", newline-separated assignments) to $NOTIFY_SOCKET. Never throws.
NotifyResult notify_systemd(const std::string& state);

// A restart in place (revocation_watch.hpp: the process execs itself, same pid) is a reload for systemd:
// RELOADING=1 now, READY=1 from the new run; the STOPPING=1 of this run's end is then not sent.
NotifyResult notify_systemd_reloading();

}  // namespace causal::dds
