#pragma once
// TBB starts its worker threads from whichever thread first runs parallel work, and Linux gives a
// new thread its creator's name: top -H, perf and semfuse-bench ingest's per-thread table then
// showed the workers' CPU as "sf-fusion" or "sf-rpc-raycast", next to the real ones.
// nameTbbWorkers() makes every worker that joins the calling thread's parallel work call itself
// "sf-worker".
namespace semfuse::server {

// Call on each thread that runs TBB algorithms, before it does; cheap after the first call on a
// thread (the observer it installs lives as long as the thread).
void nameTbbWorkers();

}  // namespace semfuse::server
