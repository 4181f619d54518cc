#pragma once
// The server's CPU priorities, three tiers. On a machine with fewer cores than busy threads the
// kernel shares a contended core by nice value, so the order here is the order in which work gets
// the CPU: the threads that give frames their pose (sf-ingest, sf-track-<k>) keep the priority
// the server started with; the map's writer and its helpers (sf-fusion, TBB's workers) run a
// little below them, so that an integration, which spreads over every core, does not make the
// next pose late; those that answer queries or derive products from the map (the services, the
// distance field, the live mesh, the occupancy grid) run well below both. Linux keeps a nice value
// per thread, and a thread starts with its creator's.
namespace semfuse::server {

// Nice values above the process's own. At 4, CFS gives the fusion about 40 % of the CPU time of a
// pose thread that wants the same core; at 12 a query thread gets about a sixth of the fusion's.
// Each still gets all of a core nobody else wants.
inline constexpr int kMapNice = 4;
inline constexpr int kQueryNice = 12;

// Sets the calling thread's nice to the process's own plus kMapNice / kQueryNice (capped at 19).
// Never raises a priority, so calling it again changes nothing. Best effort: a thread whose
// priority cannot be changed runs as before.
void lowerToMapPriority();
void lowerToQueryPriority();

// Makes TBB start its worker threads now, each lowered to the map's priority; call it from the
// main thread before any query thread runs parallel work (a worker started by a query thread
// would run the fusion's parallel work at the query's priority).
void startTbbWorkers();

}  // namespace semfuse::server
