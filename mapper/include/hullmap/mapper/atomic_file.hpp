#pragma once
// writeFileAtomically lives in the core library; this header stays for code written against the old path.
#include "hullmap/core/atomic_file.hpp"

namespace hullmap::mapper {
using core::writeFileAtomically;
}  // namespace hullmap::mapper
