// gtest checks on a ServiceProcess, for the integration, fault and security tests that start real services.
#pragma once

#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace causal::test {

// Waits up to `timeout` for the process to end: a fatal failure when it is still running, a non-fatal one
// when it ended with another code than 0; both print its output. Call it as
// ASSERT_NO_FATAL_FAILURE(expect_exit_zero(p, timeout)) so that the test stops where it would have stopped.
inline void expect_exit_zero(ServiceProcess& process, std::chrono::milliseconds timeout) {
  const auto code = process.wait(timeout);
  ASSERT_TRUE(code.has_value()) << process.output();
  EXPECT_EQ(*code, 0) << process.output();
}

}  // namespace causal::test
