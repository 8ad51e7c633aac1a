/* libFuzzer target for the streamer's frame decoder and stream parser
 * (planner/stream_frame.c). Build: cmake -DEA_FUZZ=ON with clang; run:
 *   build-fuzz/fuzz_frame -max_total_time=60 fuzz/corpus_frame
 * Invariants: no crash or sanitizer report; a frame that decodes re-encodes
 * to a frame that decodes to the same values; the parser never yields more
 * frames than fit in the input and never holds more than its buffer. */
#include "ea_planner.h"

#include <stdint.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void ea__fuzz_check(int cond) {
  if (!cond) __builtin_trap();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  /* 1. One frame as a whole. */
  ea_frame_t f, g;
  ea_error_t err;
  if (ea_frame_decode(data, size, &f, &err) == EA_OK) {
    uint8_t buf[EA_PROTO_FRAME_MAX];
    const size_t len = ea_frame_encode(&f, buf, sizeof buf);
    ea__fuzz_check(len == size);
    ea__fuzz_check(ea_frame_decode(buf, len, &g, NULL) == EA_OK);
    ea__fuzz_check(g.type == f.type && g.seq == f.seq && g.time_us == f.time_us &&
                   !memcmp(&g.sp, &f.sp, sizeof f.sp) && g.ack_seq == f.ack_seq &&
                   !memcmp(g.actual, f.actual, sizeof f.actual));
  }
  /* 2. The stream parser, fed in chunks whose sizes come from the input. */
  ea_frame_parser_t p;
  ea_frame_parser_init(&p);
  size_t off = 0, frames = 0;
  unsigned chunk = size ? data[0] : 1;
  while (off < size) {
    const size_t want = 1 + (chunk % 61);
    chunk = chunk * 1103515245u + 12345u;
    const size_t k = ea_frame_parser_feed(&p, data + off, want < size - off ? want : size - off);
    off += k;
    int r;
    while ((r = ea_frame_parser_next(&p, &f)) != 0) {
      ea__fuzz_check(p.len <= sizeof p.buf);
      if (r > 0) ++frames;
    }
    ea__fuzz_check(p.len < sizeof p.buf); /* the parser always makes room */
  }
  ea__fuzz_check(frames * (EA_PROTO_HEADER_BYTES + EA_PROTO_CRC_BYTES) <= size);
  return 0;
}
