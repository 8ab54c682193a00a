#pragma once
// Google Benchmark's console reporter that also keeps each benchmark's median (or the mean of
// its single runs), so a benchmark binary can print ratios to its peer after the runs.

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

// Keeps the median real time per iteration of every benchmark (or the mean of its runs when
// there are no aggregates), on top of the usual console output.
class MedianCollector : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const std::string& name = r.run_name.function_name;
      if (r.error_occurred) continue;
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name == "median") {
        median_ms[name] = r.GetAdjustedRealTime();
      } else if (r.run_type == Run::RT_Iteration) {
        Acc& a = single[name];
        a.sum += r.GetAdjustedRealTime();
        a.n += 1;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  // Time per frame in the reporter's unit (ms here), or < 0 if the benchmark did not run.
  double time(const std::string& name) const {
    if (auto it = median_ms.find(name); it != median_ms.end()) return it->second;
    if (auto it = single.find(name); it != single.end()) return it->second.sum / it->second.n;
    return -1.0;
  }

 private:
  struct Acc {
    double sum = 0.0;
    int n = 0;
  };

  std::map<std::string, double> median_ms;
  std::map<std::string, Acc> single;
};
