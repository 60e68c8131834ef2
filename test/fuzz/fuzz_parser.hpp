#pragma once

// The format targets' check: one parser of io/src/read_detail.hpp run twice on the input, once
// over all of its bytes in one view and one batch, once with the bytes arriving a few at a time
// (as from a pipe) and the points leaving in batches of 3. Both runs must give the same points,
// counts and error; a difference is a bug of the streaming readers.

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "read_detail.hpp"

namespace hullmap::fuzz {

using Parser = void (*)(io::detail::ByteSource&, const std::string&, io::detail::PointSink&, io::InputStats&);

struct ParseRun {
  io::Points points;
  io::InputStats stats;
  std::string error;  ///< empty when the parser returned
};

inline ParseRun runParser(Parser parse, io::detail::ByteSource& source, std::size_t batch_points) {
  ParseRun run;
  const io::PointBatchConsumer consume = [&](io::Points& batch) {
    if (batch.empty() || batch.size() > batch_points) violated("a batch of the wrong size");
    run.points.insert(run.points.end(), batch.begin(), batch.end());
  };
  io::detail::PointSink sink(batch_points, consume);
  try {
    parse(source, kInputName, sink, run.stats);
    sink.flush();
  } catch (const hullmap::Error& e) {
    run.error = e.what();
  }
  return run;
}

/// Parses `bytes` whole and in chunks (1 to 16 bytes a read, chosen by the input's size), checks
/// that both agree, then behaves as the whole parse: throws its Error, or checks its result.
inline void checkParser(Parser parse, std::string_view bytes) {
  io::detail::ByteSource whole_source(bytes);
  const ParseRun whole = runParser(parse, whole_source, std::numeric_limits<std::size_t>::max());

  std::size_t offset = 0;
  io::detail::ByteSource chunked_source(
      [&](char* buffer, std::size_t capacity) {
        const std::size_t n = std::min(capacity, bytes.size() - offset);
        std::memcpy(buffer, bytes.data() + offset, n);
        offset += n;
        return n;
      },
      1 + bytes.size() % 16);
  const ParseRun chunked = runParser(parse, chunked_source, 3);

  if (whole.error != chunked.error) violated("chunked parse error differs:", chunked.error + " vs " + whole.error);
  if (whole.error.empty()) {
    if (whole.points != chunked.points) violated("chunked parse gave other points");
    if (whole.stats.read != chunked.stats.read || whole.stats.dropped != chunked.stats.dropped) {
      violated("chunked parse gave other counts");
    }
  }
  if (!whole.error.empty()) throw hullmap::Error(whole.error);
  checkStats(whole.points, whole.stats);
}

}  // namespace hullmap::fuzz
