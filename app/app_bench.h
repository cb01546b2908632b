// Registry of `ripple bench <kind>` benchmarks. Each kind lives in its own
// cmd_bench_<kind>.cc and registers itself exactly like a subcommand
// (app/command.h):
//
//   RIPPLE_REGISTER_BENCH(tracking, "Run time against error", SetupBench);
//
// `ripple bench` (cmd_bench.cc) turns every registered kind into a
// sub-subcommand.
#ifndef RIPPLE_APP_APP_BENCH_H_
#define RIPPLE_APP_APP_BENCH_H_

#include <vector>

#include "app/command.h"

namespace ripple::app {

std::vector<CommandInfo>& BenchRegistry();

struct BenchRegistrar {
  BenchRegistrar(const char* name, const char* description,
                 CommandSetup setup) {
    BenchRegistry().push_back({name, description, std::move(setup)});
  }
};

#define RIPPLE_REGISTER_BENCH(name, description, setup)                        \
  static ::ripple::app::BenchRegistrar ripple_bench_##name(#name, description, \
                                                           setup)

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_BENCH_H_
