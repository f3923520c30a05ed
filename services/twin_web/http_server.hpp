// twin-web serves with the product's HTTP server (common/http: causal/http/http_server.hpp, shared with the
// /metrics endpoints); its names here, so the route code reads the same.
#pragma once

#include "causal/http/http_server.hpp"

namespace causal::web {

using http::HttpHandler;
using http::HttpRequest;
using http::HttpResponse;
using http::HttpServer;
using http::kMaxBodyBytes;
using http::PreRoutingHandler;
using http::ServerTls;
using http::StreamProvider;
using http::StreamSink;

}  // namespace causal::web
