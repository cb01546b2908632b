// `ripple bench <kind>`: end-to-end benchmarks that print tables and write
// CSV + PNG plots. The kinds register themselves (app/app_bench.h).
#include <algorithm>
#include <memory>

#include "app/app_bench.h"
#include "app/command.h"

namespace ripple::app {

std::vector<CommandInfo>& BenchRegistry() {
  static std::vector<CommandInfo> registry;
  return registry;
}

namespace {

CommandAction SetupBench(CLI::App* sub) {
  sub->require_subcommand(1);
  auto actions =
      std::make_shared<std::vector<std::pair<CLI::App*, CommandAction>>>();
  std::vector<CommandInfo> kinds = BenchRegistry();
  std::sort(kinds.begin(), kinds.end(),
            [](const CommandInfo& a, const CommandInfo& b) {
              return a.name < b.name;
            });
  for (const CommandInfo& kind : kinds) {
    CLI::App* k = sub->add_subcommand(kind.name, kind.description);
    actions->emplace_back(k, kind.setup(k));
  }
  return [actions] {
    for (auto& [k, action] : *actions)
      if (k->parsed()) return action();
    return Fail(kExitBadInput, "bench: no benchmark kind given");
  };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(bench, "Benchmarks: run time against error",
                        SetupBench);

}  // namespace ripple::app
