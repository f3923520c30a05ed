// The command-line options every source and every service that waits for its readers shares (one text each).
#include "causal/dds/source_driver.hpp"

#include <CLI/CLI.hpp>

#include <stdexcept>

namespace causal::dds {

void add_wait_for_option(CLI::App& app, std::vector<std::string>& wait_for, const std::string& what,
                         const std::string& example) {
  app.add_option("--wait-for", wait_for, what + ": NAME or NAME:COUNT, e.g. --wait-for " + example)
      ->check(CLI::Validator(
          [](std::string& spec) {  // refused here as a usage error (exit 2 naming the option), used later
            try {
              (void)parse_named_readers(spec);
              return std::string();
            } catch (const std::invalid_argument& e) {
              return std::string(e.what());
            }
          },
          "NAME[:COUNT]"));
}

void add_source_wait_options(CLI::App& app, SourceWaitOptions& o, bool pauses) {
  app.add_option("--wait-subscribers", o.wait_subscribers,
                 "wait until this many readers are matched before publishing (nothing is published into the void)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  add_wait_for_option(app, o.wait_for,
                      pauses ? "also wait until readers of these participants are matched, before publishing and "
                               "again whenever they go away (e.g. an estimator that restarts)"
                             : "also wait until readers of these participants are matched before publishing",
                      pauses ? "causal-estimator:2" : "causal-estimator");
  app.add_option("--wait-timeout", o.wait_timeout_s,
                 "give up waiting for readers after this many seconds (exit 3); 0 = wait for as long as it takes, "
                 "saying so every 10 s (a sensor host that boots first must not give up)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

}  // namespace causal::dds
