# OpenVDB's headers cost 5 to 9 s of compiler time per translation unit at -O3 (openvdb/openvdb.h
# alone, on the 2-core CI machine), and most sources of the server's libraries, the benchmarks
# and the map's tests include them through labeled_volume.hpp. A precompiled header per target
# parses them once per target instead of once per source: `semfuse_precompile_openvdb(target)`
# for targets with several such sources. Off with -DSEMFUSE_PRECOMPILED_HEADERS=OFF (a compiler
# that cannot read its own precompiled header falls back to the text, slower but the same code).
option(SEMFUSE_PRECOMPILED_HEADERS "Precompile OpenVDB's headers once per target" ON)

function(semfuse_precompile_openvdb target)
  if(SEMFUSE_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} PRIVATE <openvdb/openvdb.h>)
  endif()
endfunction()
