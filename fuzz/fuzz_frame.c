/* libFuzzer target for the streamer's frame decoder and stream parser
 * (planner/stream/stream_frame.c). Build: cmake -DEA_FUZZ=ON with clang; run:
 *   build-fuzz/fuzz_frame -max_total_time=60 build-fuzz/corpus-fuzz_frame fuzz/corpus/frame
 * Invariants: no crash or sanitizer report; a frame that decodes re-encodes
 * to a frame that decodes to the same values; the parser never yields more
 * frames than fit in the input and never holds more than its buffer.
 * EA_FUZZ_FRAME_SEEDS=DIR: write seed inputs (one frame of each type and a
 * stream of several) to DIR and exit (fuzz/corpus/frame was made so). */
#include "stream_wire_impl.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void ea__fuzz_seeds(const char *dir) {
  static const uint8_t types[] = {EA_FRAME_HELLO, EA_FRAME_SETPOINT, EA_FRAME_HEARTBEAT,
                                  EA_FRAME_END,   EA_FRAME_ACK,      EA_FRAME_NACK};
  uint8_t stream[8 * EA_PROTO_FRAME_MAX];
  size_t slen = 0;
  for (size_t i = 0; i < sizeof types; ++i) {
    ea_frame_t f;
    memset(&f, 0, sizeof f);
    f.version = EA_PROTO_VERSION;
    f.type = types[i];
    f.seq = (uint32_t)i;
    f.time_us = 1000u * i;
    f.flags = 1;
    f.sp.tension = 12.5;
    f.sp.shoulder_torque = -0.9;
    f.rate_hz = 500;
    f.count = 1000;
    f.heartbeat_ms = 100;
    f.ack_seq = (uint32_t)i;
    f.accepted = 3;
    f.buffer_level = 2;
    f.buffer_capacity = 64;
    f.actual[0] = 1.5;
    uint8_t buf[EA_PROTO_FRAME_MAX];
    const size_t len = ea_frame_encode(&f, buf, sizeof buf);
    if (!len || ea_frame_decode(buf, len, &f, NULL) != EA_OK) __builtin_trap();
    char path[1024];
    snprintf(path, sizeof path, "%s/type-0x%02x", dir, types[i]);
    FILE *o = fopen(path, "wb");
    if (!o) __builtin_trap();
    fwrite(buf, 1, len, o);
    fclose(o);
    memcpy(stream + slen, buf, len);
    slen += len;
  }
  char path[1024];
  snprintf(path, sizeof path, "%s/stream-all-types", dir);
  FILE *o = fopen(path, "wb");
  if (!o) __builtin_trap();
  fwrite(stream, 1, slen, o);
  fclose(o);
  exit(0);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  const char *dir = getenv("EA_FUZZ_FRAME_SEEDS");
  if (dir) ea__fuzz_seeds(dir);
  return 0;
}

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
