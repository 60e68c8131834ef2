#include "hullmap/mapper/frame.hpp"
