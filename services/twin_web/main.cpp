// twin-web: the live twin in the browser. See --help.
#include "twin_web_node.hpp"

#include "causal/history/history_store.hpp"

#include <CLI/CLI.hpp>
#include "causal/config/cli_conventions.hpp"
#include "causal/config/service_options.hpp"

int main(int argc, char** argv) {
  causal::dds::ShutdownSignal signals;  // first: every thread inherits the blocked signal mask
  causal::web::TwinWebOptions o;
  CLI::App app{"twin-web: the live twin in the browser. Subscribes to the condition vectors, causal factors, alarms,\n"
               "recommendations, asset status, prognoses, approved interventions and their outcomes on a DDS domain\n"
               "and serves one status line per asset group and, per group, the condition trends over UTC time with\n"
               "alarm bands, the current causal graph (condition-level filter, links at |z| >= 2, the root cause\n"
               "ringed), the open alarms with time scale, root cause and full reason, the prognosis, the\n"
               "recommendations with an approve button under each reliable lever, the approved interventions with\n"
               "the twin's check of each and a what-if form that asks the running alarm-recommender. Every approval\n"
               "(the page's and causal-approve's) is kept on twin-web's transient-local intervention writer while it\n"
               "runs, so a plant or recorder that starts later still receives it.\nEndpoints: / and /?group=ID (the page, with its state in the response);\n"
               "/api/state?group=ID (JSON: that group and one line per group; without ?group= every group);\n"
               "/api/events?group=ID (the same as Server-Sent Events, on change);\n"
               "/api/history?group=ID&from=UTC&to=UTC (with --db: that range from the database, as /api/state);\n"
               "POST /api/whatif {asset_group, channel, percent | delta, sustained};\n"
               "POST /api/alarm_action {asset_group, alarm_id, action, minutes, reason};\n"
               "POST /api/approve {asset_group, recommendation_id, duration_snapshots} (the approver: the\n"
               "--basic-auth-file user, else the body's user). POSTs: same origin only, with the page's X-Twin-CSRF\n"
               "token."};
  causal::dds::add_common_options(app, o.dds);
  app.add_option("--port", o.web.port, "TCP port to serve on (0: any free port, printed at start)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  app.add_option("--bind", o.web.bind,
                 "address to listen on; anything but loopback lets others ask the twin what-if questions")
      ->capture_default_str();
  app.add_option("--allowed-host", o.web.allowed_hosts,
                 "a Host name the page may be reached under besides localhost, this machine's name and IP "
                 "addresses (repeatable); any other Host is refused (DNS rebinding)");
  app.add_option("--tls-cert", o.web.tls_cert, "serve HTTPS with this PEM certificate (with --tls-key)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-key", o.web.tls_key, "the certificate's PEM private key")->check(CLI::ExistingFile);
  app.add_option("--basic-auth-file", o.web.basic_auth_file,
                 "require HTTP basic authentication on every request: a file (mode 0600) with one line "
                 "USER:PASSWORD; for any bind beyond loopback, with --tls-cert")
      ->check(CLI::ExistingFile);
  app.add_option("--chartjs", o.web.chartjs, "Chart.js file served to the page (Debian package libjs-chart.js)")
      ->capture_default_str();
  app.add_option("--history", o.limits.trend_points, "condition-trend points kept per asset group")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--approval-lead", o.web.approval_lead,
                 "the approve button: an approval starts this many snapshots after the plant's latest one (as\n"
                 "causal-approve --lead)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--approval-duration", o.web.approval_duration,
                 "the approve button: snapshots an approved change is held for (as causal-approve --duration; 0: the\n"
                 "recommendation's horizon, at least 12)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--whatif-timeout", o.web.whatif_timeout_s, "seconds a what-if question waits for its reply")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--idle-exit", o.idle_exit_s,
                 "exit this many seconds after every publisher left, once data arrived (0 = never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  causal::config::add_max_runtime_option(app, o.max_runtime_s);
  app.add_option("--db", o.db_url,
                 "the historian's database (sqlite:PATH or postgresql://..., as causal-recorder --db): drawn at start,\n"
                 "so the page is complete after a restart, and older ranges served on /api/history")
      ->check([](const std::string& url) { return causal::history::url_problem(url); });
  CAUSAL_CLI_PARSE(app, argc, argv);
  return causal::dds::run_service(signals, "twin-web", o.dds,
                                  [&] { return std::make_unique<causal::web::TwinWebNode>(std::move(o)); });
}
