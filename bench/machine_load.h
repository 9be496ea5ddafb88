// How much of the machine other processes used while a benchmark ran. The benchmark host is
// shared (builds, fuzzers, other benchmarks), and a two-thread OpenMP loop slows down sharply
// when another process holds one of the two cores, so every timed result carries this figure.
#pragma once

namespace tessera::bench {

struct CpuSample {
  long long machineBusy = 0, machineTotal = 0;  // all cores, clock ticks (/proc/stat)
  long long self = 0;                           // this process, all threads (/proc/self/stat)
};

CpuSample sampleCpu();

// Share of the machine's total CPU time between two samples taken by processes other than this
// one (0: nobody else ran; 0.5: another process held one of two cores throughout).
double othersShare(const CpuSample& before, const CpuSample& after);

// The mean time for a cache line to go from core 0 to core 1 and back (two threads pinned there
// handing an atomic back and forth), in nanoseconds; 0 on a machine with one core. On the 2-core
// VM this repository is benchmarked on it is either ~90 ns or ~400 ns, switching at minute scale
// (the host places the two vCPUs close or far apart), and work that hands data between the
// cores (many parallel phases, each reading what the other core wrote) slows down with it while
// a single parallel loop does not: every timed result carries it.
double coreRoundTripNs();

}  // namespace tessera::bench
