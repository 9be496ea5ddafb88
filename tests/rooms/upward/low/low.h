#include "core/high/high.h"
