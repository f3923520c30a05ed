// The exit codes of every executable of the product, one named set (docs/operating.md "Exit codes"). A systemd
// unit's RestartPreventExitStatus=2 keeps a service with a configuration error down; 3 and 4 are results a caller
// reads (nobody to talk to; something lost or refused), never crashes. Standard library only.
#pragma once

namespace causal::config {

enum ExitCode : int {
  kExitOk = 0,        // done: everything delivered, answered or judged
  kExitFailed = 1,    // failed: an evaluation's --check-* bar not met, an unexpected error, a restart that must be retried
  kExitUsage = 2,     // bad command line, configuration or input file, named in the message: a restart cannot help
  kExitNoPeer = 3,    // the counterpart never came or never answered in time (--wait-for readers, causal-ask's recommender)
  kExitLostOrRefused = 4,  // data lost, dropped or refused on the way, or a question refused (the summary says what)
};

}  // namespace causal::config
