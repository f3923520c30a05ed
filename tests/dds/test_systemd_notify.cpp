// The sd_notify messages for systemd Type=notify units. Truth: what a datagram socket made by this test (as
// systemd makes one) receives, byte for byte, in order.
#include "causal/dds/event_loop.hpp"
#include "causal/dds/systemd_notify.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>

#include "test_files.hpp"

namespace fs = std::filesystem;
using causal::dds::notify_systemd;
using causal::dds::NotifyResult;

namespace {

// A bound AF_UNIX datagram socket at `name` ('@' = abstract), as systemd's notification socket.
class NotifySocket {
 public:
  explicit NotifySocket(const std::string& name) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::memcpy(a.sun_path, name.data(), name.size());
    if (name[0] == '@') a.sun_path[0] = '\0';
    bound_ = ::bind(fd_, reinterpret_cast<const sockaddr*>(&a),
                    static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + name.size())) == 0;
    timeval timeout{2, 0};  // a message that never comes fails the test instead of hanging it
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }
  ~NotifySocket() { ::close(fd_); }
  bool bound() const { return bound_; }
  std::string receive() const {
    char buffer[512];
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    return n < 0 ? std::string("<nothing>") : std::string(buffer, static_cast<std::size_t>(n));
  }

 private:
  int fd_ = -1;
  bool bound_ = false;
};

class SystemdNotify : public ::testing::Test {
 protected:
  void TearDown() override { ::unsetenv("NOTIFY_SOCKET"); }
  // A listening socket at `name`, announced in NOTIFY_SOCKET as systemd does.
  void listen(const std::string& name) {
    socket_.emplace(name);
    ASSERT_TRUE(socket_->bound());
    ::setenv("NOTIFY_SOCKET", name.c_str(), 1);
  }
  const causal::test::TestTempDir temp_{"notify"};
  const fs::path& dir_ = temp_.path;
  std::optional<NotifySocket> socket_;
};

TEST_F(SystemdNotify, OutsideSystemdNothingIsSent) {
  ::unsetenv("NOTIFY_SOCKET");
  EXPECT_EQ(notify_systemd("READY=1"), NotifyResult::NoSocket);
  ::setenv("NOTIFY_SOCKET", "", 1);
  EXPECT_EQ(notify_systemd("READY=1"), NotifyResult::NoSocket);
}

TEST_F(SystemdNotify, PathSocketReceivesTheStateVerbatim) {
  ASSERT_NO_FATAL_FAILURE(listen((dir_ / "notify").string()));
  EXPECT_EQ(notify_systemd("READY=1\nSTATUS=running"), NotifyResult::Sent);
  EXPECT_EQ(socket_->receive(), "READY=1\nSTATUS=running");
}

TEST_F(SystemdNotify, AbstractSocketNamedWithAt) {
  ASSERT_NO_FATAL_FAILURE(listen("@causal_twin_notify_test_" + std::to_string(::getpid())));
  EXPECT_EQ(notify_systemd("STOPPING=1"), NotifyResult::Sent);
  EXPECT_EQ(socket_->receive(), "STOPPING=1");
}

TEST_F(SystemdNotify, NoListenerOrBadNameIsAFailureNotAnException) {
  ::setenv("NOTIFY_SOCKET", (dir_ / "nobody").c_str(), 1);
  EXPECT_EQ(notify_systemd("READY=1"), NotifyResult::Failed);
  ::setenv("NOTIFY_SOCKET", "relative/name", 1);
  EXPECT_EQ(notify_systemd("READY=1"), NotifyResult::Failed);
  ::setenv("NOTIFY_SOCKET", ("/" + std::string(200, 'x')).c_str(), 1);  // longer than sun_path
  EXPECT_EQ(notify_systemd("READY=1"), NotifyResult::Failed);
}

// Every service's run loop: READY=1 when it starts taking data, STOPPING=1 when it ends, once each.
TEST_F(SystemdNotify, RunLoopSignalsReadyThenStopping) {
  ASSERT_NO_FATAL_FAILURE(listen((dir_ / "notify").string()));
  causal::dds::EventLoop loop;
  int polls = 0;
  const auto end = loop.run({0.0, 0.3}, [&] { ++polls; return std::size_t{0}; }, [] { return std::size_t{0}; });
  EXPECT_EQ(end, causal::dds::RunEnd::MaxRuntime);
  EXPECT_EQ(socket_->receive(), "READY=1\nSTATUS=running");
  EXPECT_EQ(socket_->receive(), "STOPPING=1");
}

}  // namespace
