#include "web_server.hpp"

#include "json_reply.hpp"

#include "twin_web_assets.hpp"

#include "causal/dds/sample_limits.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace causal::web {

namespace {

using nlohmann::json;

// In index.html: replaced by the CSRF token when the page is served.
constexpr const char* kCsrfMarker = "__TWIN_CSRF_TOKEN__";
// In index.html: replaced by the state the page shows (page_json of its group), so the first response is
// complete: the page draws at once, before any event arrives (a screenshot taken at load shows the twin).
constexpr const char* kInitialStateMarker = "__TWIN_INITIAL_STATE__";

// JSON inside <script type="application/json">: "<" escaped, so no text from the twin can end the element.
std::string script_safe(const std::string& json_text) {
  std::string out;
  out.reserve(json_text.size() + 64);
  for (char c : json_text) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

void replace_marker(std::string& body, const char* marker, const std::string& value) {
  if (const auto at = body.find(marker); at != std::string::npos) body.replace(at, std::string(marker).size(), value);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool loopback_address(const std::string& a) {
  return a == "127.0.0.1" || a == "::1" || a == "localhost" || a.rfind("127.", 0) == 0;
}

std::unique_ptr<RequestGuard> make_guard(const WebOptions& o) {
  GuardOptions g;
  g.allowed_hosts = o.allowed_hosts;
  g.tls = !o.tls_cert.empty();
  if (!o.basic_auth_file.empty()) read_basic_auth_file(o.basic_auth_file, g.basic_user, g.basic_password);
  return std::make_unique<RequestGuard>(std::move(g));
}

std::unique_ptr<HttpServer> make_server(const WebOptions& o) {
  if (o.tls_cert.empty() != o.tls_key.empty()) throw std::invalid_argument("give both --tls-cert and --tls-key, or neither");
  ServerTls tls;
  if (!o.tls_cert.empty()) {
    tls.cert_pem = read_file(o.tls_cert);
    tls.key_pem = read_file(o.tls_key);
    if (tls.cert_pem.find("-----BEGIN") == std::string::npos || tls.key_pem.find("-----BEGIN") == std::string::npos) {
      throw std::invalid_argument("--tls-cert " + o.tls_cert + " / --tls-key " + o.tls_key +
                                  ": not a PEM certificate and its private key");
    }
  }
  // Server-Sent Events hold one worker per open page: more workers than that, so a few pages and the what-if
  // questions (which wait for their reply) never starve each other.
  return std::make_unique<HttpServer>(std::move(tls), static_cast<std::size_t>(o.max_event_streams) + 8);
}

// Bodies are refused before they are read (the pre-routing handler runs once the headers are in): no route
// needs a compressed body (one used to be inflated without a bound: a 408 kB gzip POST took 1.33 GB); a body
// past kMaxBodyBytes is refused by its announced length (the server drops a chunked one past it: 413).
Verdict check_body(const HttpRequest& req) {
  const std::string encoding = req.get_header_value("Content-Encoding");
  if (!encoding.empty() && encoding != "identity") {
    return {415, "compressed_body", "Content-Encoding " + encoding.substr(0, 40)};
  }
  const std::string length = req.get_header_value("Content-Length");
  const bool digits = length.find_first_not_of("0123456789") == std::string::npos;
  if (!length.empty() && (!digits || length.size() > 9 || std::stoul(length) > kMaxBodyBytes)) {
    return {413, "body_too_large", "Content-Length " + length.substr(0, 40)};
  }
  return {};
}

std::string host_name() {
  char host[128] = "host";
  gethostname(host, sizeof host - 1);
  return host;
}

// The question in the body, checked like causal-ask checks its command line. Returns the error, or "".
std::string parse_question(const json& body, const std::vector<std::string>& channels, causal_twin::WhatIfRequest& r,
                           bool& percent) {
  if (!body.is_object()) return "the body must be a JSON object";
  if (!body.contains("asset_group") || !body["asset_group"].is_string() || body["asset_group"].get<std::string>().empty()) {
    return "asset_group (string) is required";
  }
  if (body["asset_group"].get<std::string>().size() > dds::kMaxIdBytes) {
    return "asset_group is longer than " + std::to_string(dds::kMaxIdBytes) + " bytes";
  }
  if (!body.contains("channel") || !body["channel"].is_number_integer()) return "channel (1-based integer) is required";
  const long channel = body["channel"].get<long>();
  const long max_channel = channels.empty() ? 64 : static_cast<long>(channels.size());
  if (channel < 1 || channel > max_channel) return "channel must be in 1.." + std::to_string(max_channel);
  const bool has_percent = body.contains("percent"), has_delta = body.contains("delta");
  if (has_percent == has_delta) return "give exactly one of percent and delta";
  const json& v = has_percent ? body["percent"] : body["delta"];
  if (!v.is_number()) return has_percent ? "percent must be a number" : "delta must be a number";
  const double x = v.get<double>();
  if (!std::isfinite(x)) return "the change must be finite";
  if (has_percent && x <= -100.0) return "percent must be > -100";
  bool sustained = true;
  if (body.contains("sustained")) {
    if (!body["sustained"].is_boolean()) return "sustained must be true or false";
    sustained = body["sustained"].get<bool>();
  }
  percent = has_percent;
  r.asset_group(body["asset_group"].get<std::string>());
  r.intervene_channel(static_cast<std::uint16_t>(channel));
  // A level change in percent on the log-level model, as causal-ask --percent.
  r.delta(has_percent ? std::log1p(x / 100.0) : x);
  r.sustained(sustained);
  return {};
}

json reply_json(const causal_twin::WhatIfReply& reply, const causal_twin::WhatIfRequest& request, bool percent,
                const std::vector<std::string>& channels) {
  auto numbers = [](const std::vector<double>& v) {
    json a = json::array();
    for (double x : v) a.push_back(std::isfinite(x) ? json(x) : json(nullptr));
    return a;
  };
  return {{"answered", true},
          {"ok", reply.ok()},
          {"error", reply.error()},
          {"text", reply.text()},
          {"request_id", reply.request_id()},
          {"asset_group", reply.asset_group()},
          {"intervene_channel", request.intervene_channel()},
          {"delta", request.delta()},
          {"sustained", request.sustained()},
          {"percent", percent},
          {"channels", channels},
          {"effect_immediate", numbers(reply.effect_immediate())},
          {"effect_steady_state", numbers(reply.effect_steady_state())},
          {"effect_low", numbers(reply.effect_low())},
          {"effect_high", numbers(reply.effect_high())},
          {"answer_kind", reply.answer_kind()},
          {"horizon_snapshots", reply.horizon_snapshots()},
          {"spectral_radius", std::isfinite(reply.spectral_radius()) ? json(reply.spectral_radius()) : json(nullptr)},
          {"draws", reply.draws()},
          {"unstable_draws", reply.unstable_draws()},
          {"effect_median", numbers(reply.effect_median())},
          {"effect_percent", numbers(reply.effect_percent())},
          {"effect_percent_low", numbers(reply.effect_percent_low())},
          {"effect_percent_high", numbers(reply.effect_percent_high())},
          {"summary", reply.summary()}};
}

}  // namespace

WebServer::WebServer(WebOptions options, TwinState& state, WhatIfBridge& whatif,
                     std::function<std::size_t()> whatif_readers)
    : options_(std::move(options)),
      state_(state),
      whatif_(whatif),
      whatif_readers_(std::move(whatif_readers)),
      guard_(make_guard(options_)),
      server_(make_server(options_)) {
  if (options_.port < 0 || options_.port > 65535) throw std::invalid_argument("--port must be in 0..65535");
  if (!loopback_address(options_.bind) && (options_.tls_cert.empty() || !guard_->authenticating())) {
    spdlog::warn("twin-web listens on {} {}: anyone who can reach it {} (give --tls-cert/--tls-key and "
                 "--basic-auth-file)", options_.bind, options_.tls_cert.empty() ? "in clear text" : "over TLS",
                 guard_->authenticating() ? "can read the traffic" : "can read the twin and ask what-if questions");
  }
  chartjs_ = read_file(options_.chartjs);
  if (chartjs_.empty()) {
    spdlog::warn("cannot read Chart.js at {} (Debian package libjs-chart.js): the page shows no trend chart",
                 options_.chartjs);
  }
  guard_requests();
  routes();
  port_ = server_->listen(options_.bind, options_.port);
  if (port_ <= 0) {
    throw std::runtime_error("cannot listen on " + options_.bind + ":" + std::to_string(options_.port) +
                             (options_.tls_cert.empty() ? std::string(" (address in use, or not an address of this host)")
                                                        : " (address in use, not an address of this host, or --tls-cert " +
                                                              options_.tls_cert + " / --tls-key " + options_.tls_key +
                                                              " not a PEM certificate and its private key)"));
  }
}

WebServer::~WebServer() { stop(); }

void WebServer::start() {}  // the server serves from listen() on (its own polling thread)

void WebServer::stop() {
  stopping_.store(true);
  if (server_) server_->stop();
}

namespace {

void count_refusal(const std::string& reason, const std::string& detail, const std::string& request) {
  auto& counter = metrics::process_metrics().counter(
      "web_requests_refused_total", "HTTP requests refused: Host not allowed, cross-origin, no CSRF token, "
      "no credentials, a compressed or too large body, too many headers, past the request deadline, a bad query, "
      "a failed handler",
      {{"reason", reason}});
  counter.inc();
  const auto n = static_cast<std::uint64_t>(counter.value());
  if (n == 1 || n % 100 == 0) {
    spdlog::warn("refused {}: {} ({}; {} refused for this reason so far)", request, reason, detail, n);
  }
}

}  // namespace

void WebServer::guard_requests() {
  server_->set_refusal_observer(
      [](const std::string& reason, const std::string& detail) { count_refusal(reason, detail, "a request"); });
  std::vector<std::pair<std::string, std::string>> headers;
  for (const auto& [k, v] : security_headers()) headers.emplace_back(k, v);
  server_->set_default_headers(headers);
  server_->set_pre_routing_handler([this](const HttpRequest& req, HttpResponse& res) {
    RequestFacts f{req.method,
                   req.get_header_value("Host"),
                   req.get_header_value("Origin"),
                   req.get_header_value("Sec-Fetch-Site"),
                   req.get_header_value("X-Twin-CSRF"),
                   req.get_header_value("Authorization")};
    Verdict v = guard_->check(f);
    if (v.status == 0) v = check_body(req);
    if (v.status == 0) return false;
    count_refusal(v.reason, v.detail, req.method + " " + req.path + " from " + req.remote_addr);
    if (v.status == 401) res.set_header("WWW-Authenticate", "Basic realm=\"causal-twin\", charset=\"UTF-8\"");
    send_unanswered(res, v.status, v.reason + ": " + v.detail);
    return true;
  });
}

void WebServer::routes() {
  auto& s = *server_;
  for (const auto& asset : kEmbeddedAssets) {
    // The page carries this process's CSRF token (a marker in index.html, replaced when the page is served);
    // only it can read it.
    std::string body(asset.body.data(), asset.body.size());
    replace_marker(body, kCsrfMarker, guard_->csrf_token());
    const bool page = body.find(kInitialStateMarker) != std::string::npos;
    auto serve = [this, asset, body, page](const HttpRequest& req, HttpResponse& res) {
      if (!page) {
        res.set_header("Cache-Control", "no-cache");
        res.set_content(body, std::string(asset.content_type));
        return;
      }
      // ?group=ID, or the group the page would choose itself: the state it shows is in the response.
      const std::string group = req.has_param("group") ? req.get_param_value("group") : state_.default_group();
      std::string filled = body;
      replace_marker(filled, kInitialStateMarker, script_safe(state_.page_json(group)));
      res.set_header("Cache-Control", "no-store");
      res.set_content(filled, std::string(asset.content_type));
    };
    s.Get(std::string(asset.path), serve);
    if (asset.path == "/index.html") s.Get("/", serve);
  }
  s.Get("/vendor/chart.min.js", [this](const HttpRequest&, HttpResponse& res) {
    if (chartjs_.empty()) {
      res.status = 404;
      res.set_content("Chart.js not installed (" + options_.chartjs + ")", "text/plain");
      return;
    }
    res.set_header("Cache-Control", "max-age=3600");
    res.set_content(chartjs_, "text/javascript; charset=utf-8");
  });
  // ?group=ID: what the page shows (every group's overview, that group in full); without: everything.
  s.Get("/api/state", [this](const HttpRequest& req, HttpResponse& res) {
    res.set_header("Cache-Control", "no-store");
    if (req.has_param("group")) {
      res.set_content(state_.page_json(req.get_param_value("group")), "application/json");
      return;
    }
    const auto body = state_.json();
    res.set_content(*body, "application/json");
  });
  history_route();
  alarm_action_route();
  approve_route();
  s.Get("/api/events", [this](const HttpRequest& req, HttpResponse& res) {
    if (event_streams_.fetch_add(1) >= options_.max_event_streams) {
      --event_streams_;
      send_json(res, 503, {{"error", "too many open event streams: poll /api/state"}});
      return;
    }
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Accel-Buffering", "no");
    // The page's view of one group (?group=ID; none: the overview alone, to choose one), one event per change
    // of it, at most four a second; a comment line every 15 s keeps proxies open.
    const std::string group = req.has_param("group") ? req.get_param_value("group") : std::string();
    auto seen = std::make_shared<TwinState::Versions>(TwinState::Versions{~std::uint64_t{0}, 0});
    auto quiet = std::make_shared<int>(0);
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, group, seen, quiet](const StreamSink& sink) {
          if (stopping_.load()) return false;
          if (!state_.wait_for_change(group, *seen, std::chrono::milliseconds(500))) {
            if (++*quiet < 30) return true;
            *quiet = 0;
            return sink(": keep-alive\n\n");
          }
          *quiet = 0;
          *seen = state_.versions(group);
          const std::string body = state_.page_json(group);
          std::string event;
          event.reserve(body.size() + 32);
          event.append("event: state\ndata: ").append(body).append("\n\n");
          if (!sink(event)) return false;
          std::this_thread::sleep_for(std::chrono::milliseconds(250));
          return !stopping_.load();
        },
        [this] { --event_streams_; });
  });
  s.Post("/api/whatif", [this](const HttpRequest& req, HttpResponse& res) {
    const std::optional<json> parsed = json_body(req, res);
    if (!parsed) return;
    const json& body = *parsed;
    causal_twin::WhatIfRequest request;
    bool percent = false;
    const std::string group = body.is_object() && body.contains("asset_group") && body["asset_group"].is_string()
                                  ? body["asset_group"].get<std::string>()
                                  : std::string();
    const std::vector<std::string> channels = state_.channels(group);
    if (const std::string problem = parse_question(body, channels, request, percent); !problem.empty()) {
      send_unanswered(res, 400, problem);
      return;
    }
    static const std::string prefix = "twin-web/" + host_name() + "/" + std::to_string(getpid()) + "/";
    request.request_id(prefix + std::to_string(++next_request_));
    const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.whatif_timeout_s * 1000.0));
    const WhatIfBridge::Outcome out = whatif_.ask(request, timeout);
    if (out.status == WhatIfBridge::Status::Answered) {
      send_json(res, 200, reply_json(out.reply, request, percent, channels));
      return;
    }
    if (out.status == WhatIfBridge::Status::Stopped) {
      send_unanswered(res, 503, "twin-web is stopping");
      return;
    }
    const bool reader = whatif_readers_ && whatif_readers_() > 0;
    char msg[160];
    std::snprintf(msg, sizeof msg, "no reply within %.0f s%s", options_.whatif_timeout_s,
                  reader ? "" : ": no alarm-recommender reads what-if requests");
    send_unanswered(res, 504, msg);
  });
}

// ?group=ID&from=UTC&to=UTC: a range from the historian's database (history_routes.hpp: the logic).
void WebServer::history_route() {
  server_->Get("/api/history", [this](const HttpRequest& req, HttpResponse& res) {
    HistoryRoutes none(nullptr, 0);
    const HistoryReply reply = (history_ ? *history_ : none)
                                   .range(req.get_param_value("group"), req.get_param_value("from"),
                                          req.get_param_value("to"));
    // A range it cannot read (no group, a time that is not UTC, from after to) is counted as the server's
    // refusals are (bad_query).
    if (reply.status == 400) count_refusal("bad_query", reply.body, "GET /api/history from " + req.remote_addr);
    res.status = reply.status;
    res.set_header("Cache-Control", "no-store");
    res.set_content(reply.body, "application/json");
  });
}

}  // namespace causal::web
