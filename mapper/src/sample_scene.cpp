#include "hullmap/mapper/sample_scene.hpp"
