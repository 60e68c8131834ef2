#pragma once
// hullmap::Error lives in the core library; this header stays for code written against the old path.
#include "hullmap/core/error.hpp"
