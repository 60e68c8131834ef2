#include "hullmap/clustering/dbscan.hpp"
