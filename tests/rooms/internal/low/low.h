#include "core/low/detail.h"
