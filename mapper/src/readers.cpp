#include "hullmap/mapper/readers.hpp"
