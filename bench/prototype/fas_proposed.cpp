#include "bench/prototype/fas_proposed.h"

#include "bench/prototype/fas_proposed_kernel.h"  // defines tessera::proposed::refineRingBlocks
