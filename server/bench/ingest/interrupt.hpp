#pragma once
// Ctrl-C / SIGTERM during `semfuse-bench ingest`: the runs end early, the server is still
// stopped and the partial results are printed. Every loop of the bench polls the flag.
namespace semfuse::bench::ingest {

void installInterruptHandler();
bool interrupted();

}  // namespace semfuse::bench::ingest
