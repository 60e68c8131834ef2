#include "hullmap/clustering/obstacles.hpp"
