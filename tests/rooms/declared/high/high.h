#include "core/low/low.h"
