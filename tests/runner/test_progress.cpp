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
  p.set_running_jobs({{"job-b", 0.5}, {"job-c", 0.5}});
  // 3 jobs left, of which two are half done: 2 jobs of 10 s on 2 workers.
  EXPECT_EQ(p.eta(), "0:10");
  // A failed job counts as done but not as a measurement.
  p.finished("failed", "job-d", "crash", 1000.0);
  p.set_running_jobs({{"job-b", 0.9}, {"job-c", 0.9}});
  EXPECT_EQ(p.eta(), "0:01"); // 0.2 job x 10 s / 2
}

// A running job's rest comes from its own rate once it has progressed; the jobs not started
// from the cost model's estimates, scaled by how the finished jobs compared with theirs.
TEST(Progress, EtaFromTheRunningJobsOwnRatesAndTheCostModel) {
  std::ostringstream out;
  Progress p(out, false, 4, 2);
  p.set_plan(4 * 50.0, 4);    // four jobs estimated at 50 s each
  EXPECT_EQ(p.eta(), "1:40"); // 200 s on 2 workers
  p.job_started(50.0);
  p.job_started(50.0);
  p.set_running(2);
  // One running job at 25 % after 100 s (300 s left at its own rate), the other at 1 % (too
  // early for a rate: its estimate less its 10 s, 40 s); two jobs of 50 s not started.
  p.set_running_jobs({{"a", 0.25, 100.0, 50.0}, {"b", 0.01, 10.0, 50.0}});
  EXPECT_EQ(p.eta(), "5:00"); // (300 + 40 + 100) / 2 = 220 s, but the 300 s job is longer
  // b finished in 100 s against its estimate of 50: the estimates left are doubled. c starts.
  p.finished("done", "b", "100 s", 100.0, 50.0);
  p.job_started(50.0);
  p.set_running_jobs({{"a", 0.25, 100.0, 50.0}, {"c", 0.5, 50.0, 50.0}});
  // a: 300 s; c: 50 s at its own rate; one job not started, 2 x 50 s: 450 / 2 < 300.
  EXPECT_EQ(p.eta(), "5:00");
  p.set_running_jobs({{"a", 0.9, 900.0, 50.0}, {"c", 0.5, 50.0, 50.0}});
  EXPECT_EQ(p.eta(), "2:05"); // (100 + 50 + 100) / 2
}

// A job resumed from a checkpoint at 16 % that has reached 19 % 13 minutes later has progressed
// 3 % in that time: about 5.8 hours left, not the 57 minutes that 19 % in 13 minutes would say.
TEST(Progress, AResumedJobsRateCountsOnlyTheProgressSinceItsCheckpoint) {
  std::ostringstream out;
  Progress p(out, false, 1, 1);
  p.set_running(1);
  p.set_running_jobs({{"fsi", 0.19, 780.0, std::nullopt, 0.16}});
  EXPECT_EQ(p.eta(), "5:51:00"); // 780 s x 0.81 / 0.03 = 21 060 s
  // Too little progress since the checkpoint for a rate: the estimate of the part left.
  p.set_running_jobs({{"fsi", 0.17, 60.0, 1000.0, 0.16}});
  EXPECT_EQ(p.eta(), "13:00"); // 1000 s x (1 - 0.16) - 60 s
}

TEST(Progress, PlainModeWritesLogLinesAndPeriodicProgress) {
  std::ostringstream out;
  Progress p(out, false, 3, 2);
  p.set_log_every_s(0.0);
  p.finished("done", "abc n_side=8", "0.1 s  err=0.01", 0.1);
  p.set_running(2);
  p.set_running_jobs({{"deadbeef", 0.25}, {"cafef00d", 0.75}});
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
  p.set_running_jobs({{"deadbeef", 0.5}});
  p.tick();
  std::string s = out.str();
  EXPECT_EQ(s.rfind("\r\033[K", 0), 0u);
  EXPECT_CONTAINS(s, "ETA ?");
  EXPECT_LE(s.size() - 4, 63u); // cut to the width (minus the control sequence)
  EXPECT_CONTAINS(s, "...");
  EXPECT_EQ(s.find('\n'), std::string::npos);
  // Every finished job's line is printed above the live line, which is redrawn below it.
  p.finished("done", "job-a", "1 s", 1.0);
  EXPECT_CONTAINS(out.str(), "\r\033[K[1/2] done     job-a  1 s\n\r\033[K[1/2] running");
  p.finished("failed", "job-b", "SIGSEGV", 1.0);
  EXPECT_CONTAINS(out.str(), "[2/2] failed   job-b  SIGSEGV\n");
  p.close();
  EXPECT_EQ(out.str().substr(out.str().size() - 4), "\r\033[K");
  std::ostringstream wide;
  Progress q(wide, true, 2, 1);
  q.set_running(1);
  q.set_running_jobs({{"deadbeef", 0.5}});
  q.tick();
  EXPECT_CONTAINS(wide.str(), "| deadbeef 50%");
}
