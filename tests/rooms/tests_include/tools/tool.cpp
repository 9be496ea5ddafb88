#include "tests/support/mesh_equality.h"
