#include "hullmap/mapper/occupancy_map.hpp"
