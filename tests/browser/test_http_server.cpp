// twin-web's HTTP server (services/twin_web/http_server.hpp) on a loopback port, with a real client: exact and
// pattern routes (how other routes are registered), 404 for what is not routed, HEAD answered as GET without a
// body, the pre-routing refusal, the default headers, a handler that waits without stalling other clients.
#include "http_server.hpp"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <future>
#include <thread>

namespace {

using causal::web::HttpRequest;
using causal::web::HttpResponse;
using causal::web::HttpServer;

TEST(HttpServer, RoutesExactAndPatternPathsAndRefusesTheRest) {
  HttpServer server({}, 4);
  server.set_default_headers({{"X-Frame-Options", "DENY"}});
  server.Get("/api/state", [](const HttpRequest& req, HttpResponse& res) {
    res.set_content("group=" + req.get_param_value("group"), "text/plain");
  });
  server.Post(R"(/api/alarms/([^/]+)/ack)", [](const HttpRequest& req, HttpResponse& res) {
    res.status = 202;
    res.set_content(req.matches.at(1) + ":" + req.body, "text/plain");
  });
  server.set_pre_routing_handler([](const HttpRequest& req, HttpResponse& res) {
    if (req.get_header_value("x-refuse").empty()) return false;
    res.status = 403;
    return true;
  });
  const int port = server.listen("127.0.0.1", 0);
  ASSERT_GT(port, 0);
  httplib::Client client("127.0.0.1", port);

  auto get = client.Get("/api/state?group=line%20a");
  ASSERT_TRUE(get);
  EXPECT_EQ(get->status, 200);
  EXPECT_EQ(get->body, "group=line a");
  EXPECT_EQ(get->get_header_value("X-Frame-Options"), "DENY");
  EXPECT_EQ(get->get_header_value("Content-Type"), "text/plain");

  auto head = client.Head("/api/state");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_TRUE(head->body.empty());

  auto ack = client.Post("/api/alarms/A-17/ack", "by operator", "text/plain");
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, 202);
  EXPECT_EQ(ack->body, "A-17:by operator");

  auto wrong_method = client.Post("/api/state", "", "text/plain");
  ASSERT_TRUE(wrong_method);
  EXPECT_EQ(wrong_method->status, 404);
  auto unknown = client.Get("/api/alarms/A-17/ack");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  auto refused = client.Get("/api/state", httplib::Headers{{"X-Refuse", "1"}});
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 403);
  server.stop();
}

TEST(HttpServer, AWaitingHandlerDoesNotStallOtherClients) {
  HttpServer server({}, 4);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  server.Get("/slow", [released](const HttpRequest&, HttpResponse& res) {
    released.wait_for(std::chrono::seconds(10));
    res.set_content("slow", "text/plain");
  });
  server.Get("/fast", [](const HttpRequest&, HttpResponse& res) { res.set_content("fast", "text/plain"); });
  const int port = server.listen("127.0.0.1", 0);
  ASSERT_GT(port, 0);
  auto slow = std::async(std::launch::async, [port] { return httplib::Client("127.0.0.1", port).Get("/slow"); });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const auto start = std::chrono::steady_clock::now();
  auto fast = httplib::Client("127.0.0.1", port).Get("/fast");
  const auto took = std::chrono::steady_clock::now() - start;
  ASSERT_TRUE(fast);
  EXPECT_EQ(fast->body, "fast");
  EXPECT_LT(took, std::chrono::seconds(1));
  release.set_value();
  auto s = slow.get();
  ASSERT_TRUE(s);
  EXPECT_EQ(s->body, "slow");
  server.stop();
}

}  // namespace
