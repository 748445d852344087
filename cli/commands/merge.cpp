#include <cstdio>

#include "commands.hpp"
#include "plumetrace/experiment/store.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

CLI::App* MergeCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "merge", "merge the stores of a sweep's shards (plumetrace sweep --shard) into one store");
  sub->add_option("parts", parts, "the parts' results stores")->required()->check(not_empty());
  sub->add_option("--store", store, "the merged results store (created if needed)")
      ->required()
      ->check(not_empty());
  return sub;
}

int MergeCommand::run() {
  const MergeReport report = merge_stores(parts, store);
  std::printf(
      "merged %zu part(s) into %s: %lld runs added, %lld already there; %lld runs in the "
      "store\n",
      parts.size(), store.c_str(), static_cast<long long>(report.added),
      static_cast<long long>(report.already), static_cast<long long>(report.total));
  for (const auto& gap : report.gaps) {
    std::fprintf(stderr, "plumetrace: warning: sweep %s: %lld of %lld runs are missing\n",
                 gap.sweep.c_str(), static_cast<long long>(gap.expected - gap.present),
                 static_cast<long long>(gap.expected));
  }
  if (!report.missing_shards.empty()) {
    std::string shards;
    for (const auto& s : report.missing_shards) shards += (shards.empty() ? "" : ", ") + s;
    std::fprintf(stderr, "plumetrace: warning: no part holds shard(s) %s\n", shards.c_str());
  }
  if (!report.gaps.empty()) {
    std::fprintf(stderr,
                 "plumetrace: warning: the merged store is incomplete; merge the missing parts "
                 "into it, or run plumetrace sweep SWEEP.toml --store %s to compute the rest\n",
                 store.c_str());
  }
  return 0;
}

}  // namespace plumetrace::cli
