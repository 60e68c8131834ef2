#include "hullmap/collision/path_check.hpp"
