// The product's HTTP server (common/http: twin-web, /metrics) on a loopback port, with a real client: exact and
// pattern routes (how other routes are registered), 404 for what is not routed, HEAD answered as GET without a
// body, the pre-routing refusal, the default headers, a handler that waits without stalling other clients; query
// strings bounded (argument count, length, UTF-8: 400 bad_query) and a throwing handler answered 500.
#include "causal/http/http_server.hpp"
#include "http_test_client.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <future>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace {

using causal::http::HttpRequest;
using causal::http::HttpResponse;
using causal::http::HttpServer;
using causal::test::http_request;

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
  auto get = http_request(port, "GET", "/api/state?group=line%20a");
  ASSERT_TRUE(get);
  EXPECT_EQ(get->status, 200);
  EXPECT_EQ(get->body, "group=line a");
  EXPECT_EQ(get->get_header_value("X-Frame-Options"), "DENY");
  EXPECT_EQ(get->get_header_value("Content-Type"), "text/plain");

  auto head = http_request(port, "HEAD", "/api/state");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_TRUE(head->body.empty());

  auto ack = http_request(port, "POST", "/api/alarms/A-17/ack", "Content-Type: text/plain\r\n", "by operator");
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, 202);
  EXPECT_EQ(ack->body, "A-17:by operator");

  auto wrong_method = http_request(port, "POST", "/api/state", "Content-Type: text/plain\r\n");
  ASSERT_TRUE(wrong_method);
  EXPECT_EQ(wrong_method->status, 404);
  auto unknown = http_request(port, "GET", "/api/alarms/A-17/ack");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  auto refused = http_request(port, "GET", "/api/state", "X-Refuse: 1\r\n");
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
  auto slow = std::async(std::launch::async, [port] { return http_request(port, "GET", "/slow"); });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const auto start = std::chrono::steady_clock::now();
  auto fast = http_request(port, "GET", "/fast");
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

TEST(HttpServer, QueriesAreBoundedAndAThrowingHandlerAnswers500) {
  HttpServer server({}, 2);
  std::mutex m;
  std::map<std::string, int> refused;
  server.set_refusal_observer([&](const std::string& reason, const std::string&) {
    std::lock_guard<std::mutex> lock(m);
    ++refused[reason];
  });
  server.Get("/api/state", [](const HttpRequest& req, HttpResponse& res) {
    res.set_content("group=" + req.get_param_value("group"), "text/plain");
  });
  server.Get("/boom", [](const HttpRequest&, HttpResponse&) { throw std::runtime_error("handler failed"); });
  const int port = server.listen("127.0.0.1", 0);
  ASSERT_GT(port, 0);
  const auto status = [port](const std::string& target) {
    const auto r = http_request(port, "GET", target);
    return r ? r->status : 0;
  };
  std::string many = "/api/state?a0=0";
  for (int i = 1; i <= 16; ++i) many += "&a" + std::to_string(i) + "=" + std::to_string(i);  // 17 arguments
  EXPECT_EQ(status("/api/state?group=%FF"), 400);                                  // not UTF-8
  EXPECT_EQ(status("/api/state?group=%C0%AF"), 400);                               // overlong encoding of '/'
  EXPECT_EQ(status("/api/state?group=%ED%A0%80"), 400);                            // a UTF-16 surrogate
  EXPECT_EQ(status("/api/state?group=" + std::string(1100, 'a')), 400);            // past 1 KiB
  EXPECT_EQ(status(many), 400);
  const auto accented = http_request(port, "GET", "/api/state?group=l%C3%ADnea-%F0%9F%94%A7");
  ASSERT_TRUE(accented);
  EXPECT_EQ(accented->status, 200);
  EXPECT_EQ(accented->body, "group=l\xC3\xADnea-\xF0\x9F\x94\xA7");
  EXPECT_EQ(status("/api/state?group=" + std::string(1000, 'a')), 200);
  EXPECT_EQ(status("/boom"), 500);
  EXPECT_EQ(status("/api/state"), 200) << "the server goes on after a handler threw";
  server.stop();
  std::lock_guard<std::mutex> lock(m);
  EXPECT_EQ(refused["bad_query"], 5);
  EXPECT_EQ(refused["handler_error"], 1);
}

}  // namespace
