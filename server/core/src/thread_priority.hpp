#pragma once
// The server's CPU priorities. On a machine with fewer cores than busy threads, the threads that
// take frames in and fuse them (sf-ingest, sf-fusion, TBB's workers) keep the default priority,
// and those that answer queries or derive products from the map (the services, the distance
// field, the live mesh, the occupancy grid) run below them: the kernel then gives frames the CPU
// first and the queries what is left, instead of sharing it evenly and dropping frames. Linux
// keeps a nice value per thread, and a thread starts with its creator's.
namespace semfuse::server {

// How much nicer than the fusion a query thread is: at 10, CFS gives it about a tenth of the CPU
// time of a default thread that wants the same core, and all of a core nobody else wants.
inline constexpr int kQueryNice = 10;

// Raises the calling thread's nice value by kQueryNice, once per thread (later calls do nothing).
// Best effort: a thread whose priority cannot be changed runs as before.
void lowerToQueryPriority();

// Makes TBB start its worker threads now, from the calling thread, so that they take its
// priority; call it from the main thread before any query thread runs parallel work (a worker
// started by a query thread would run the fusion's parallel work at the query's priority).
void startTbbWorkers();

}  // namespace semfuse::server
