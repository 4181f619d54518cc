#pragma once
// The load bench's tables (inputs, stages, queries, CPU, memory, the idle raycast) and the
// comparison with the service's targets; and the verdict of --check, which asks only that
// nothing was lost without a counted reason and that every query got a reply.
#include <string>
#include <vector>

#include "ingest/preloaded_frames.hpp"
#include "load_options.hpp"
#include "load_result.hpp"

namespace semfuse::bench::load {

void printLoadReport(const LoadResult& result, const LoadOptions& options, const ingest::Preloaded& data);

// Two runs of the same load, the server on CPU 0 alone and on every core: throughput and its ratio.
void printCoreComparison(const LoadResult& one_core, const LoadResult& every_core);

// What --check fails on; empty when the run passes.
std::vector<std::string> checkFailures(const LoadResult& result);

}  // namespace semfuse::bench::load
