// The progress display: the ETA from measured job times and running jobs' fractions, the live
// line (redrawn in place, cut to the terminal width) and the plain log lines used when stdout is
// not a terminal.
#include "progress.hpp"

#include "helpers.hpp"

#include <gtest/gtest.h>

#include <sstream>

using namespace sph::runner;

TEST(Progress, EtaFromMeasuredJobTimesAndRunningFractions) {
  std::ostringstream out;
  Progress p(out, false, 4, 2);
  EXPECT_EQ(p.eta(), "?"); // nothing measured yet
  p.set_prior_job_s(20.0); // earlier attempts of the study: 4 jobs x 20 s on 2 workers
  EXPECT_EQ(p.eta(), "0:40");
  p.finished("done", "job-a", "10 s", 10.0); // this run's measurement replaces the prior
  p.set_running(2);
  p.set_fractions({{"job-b", 0.5}, {"job-c", 0.5}});
  // 3 jobs left, of which two are half done: 2 jobs of 10 s on 2 workers.
  EXPECT_EQ(p.eta(), "0:10");
  // A failed job counts as done but not as a measurement.
  p.finished("failed", "job-d", "crash", 1000.0);
  p.set_fractions({{"job-b", 0.9}, {"job-c", 0.9}});
  EXPECT_EQ(p.eta(), "0:01"); // 0.2 job x 10 s / 2
}

TEST(Progress, PlainModeWritesLogLinesAndPeriodicProgress) {
  std::ostringstream out;
  Progress p(out, false, 3, 2);
  p.set_log_every_s(0.0);
  p.finished("done", "abc n_side=8", "0.1 s  err=0.01", 0.1);
  p.set_running(2);
  p.set_fractions({{"deadbeef", 0.25}, {"cafef00d", 0.75}});
  p.tick();
  p.close();
  std::string s = out.str();
  EXPECT_EQ(s.find('\r'), std::string::npos);
  EXPECT_EQ(s.find('\033'), std::string::npos);
  EXPECT_CONTAINS(s, "[1/3] done     abc n_side=8  0.1 s  err=0.01\n");
  EXPECT_CONTAINS(s, "progress: [1/3] running 2, failed 0, diverged 0, elapsed 0:00, ETA 0:00 | "
                     "deadbeef 25%, cafef00d 75%\n");
}

TEST(Progress, LiveLineIsRedrawnInPlaceAndFitsTheTerminal) {
  std::ostringstream out;
  Progress p(out, true, 2, 1);
  p.set_width(64);
  p.set_running(1);
  p.set_fractions({{"deadbeef", 0.5}});
  p.tick();
  std::string s = out.str();
  EXPECT_EQ(s.rfind("\r\033[K", 0), 0u);
  EXPECT_CONTAINS(s, "ETA ?");
  EXPECT_LE(s.size() - 4, 63u); // cut to the width (minus the control sequence)
  EXPECT_CONTAINS(s, "...");
  EXPECT_EQ(s.find('\n'), std::string::npos);
  // A done job only updates the line; a failure is printed above it.
  p.finished("done", "job-a", "1 s", 1.0);
  EXPECT_EQ(out.str().find('\n'), std::string::npos);
  p.finished("failed", "job-b", "SIGSEGV", 1.0);
  EXPECT_CONTAINS(out.str(), "[2/2] failed   job-b  SIGSEGV\n");
  p.close();
  EXPECT_EQ(out.str().substr(out.str().size() - 4), "\r\033[K");
  std::ostringstream wide;
  Progress q(wide, true, 2, 1);
  q.set_running(1);
  q.set_fractions({{"deadbeef", 0.5}});
  q.tick();
  EXPECT_CONTAINS(wide.str(), "| deadbeef 50%");
}
