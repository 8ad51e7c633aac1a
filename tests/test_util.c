/* The utility layer (model/util, private header ea_util.h): CRC-32 against the
 * check value of the CRC catalogue, CSV quoting against RFC 4180 (quotes
 * doubled, the field enclosed), JSON string escapes against RFC 8259,
 * file-name extensions, the monotonic clock. */
#include "ea_test.h"
#include "ea_util.h"

#include <string.h>

/* What f wrote to fp, as a string in buf. */
static const char *captured(FILE *fp, char *buf, size_t len) {
  const long n = ftell(fp);
  rewind(fp);
  const size_t got = fread(buf, 1, len - 1, fp);
  buf[got] = '\0';
  return n >= 0 && (size_t)n == got ? buf : "";
}

static void test_crc(void) {
  /* CRC-32/ISO-HDLC check value (CRC catalogue; zlib's crc32 of "123456789") */
  ea_test_true(ea_crc32(0, "123456789", 9) == 0xCBF43926u, "CRC-32 check value 0xCBF43926");
  const uint32_t part = ea_crc32(0, "1234", 4);
  ea_test_true(ea_crc32(part, "56789", 5) == 0xCBF43926u, "CRC-32 continued over two pieces");
  ea_test_true(ea_crc32(0, "", 0) == 0u, "CRC-32 of nothing is 0");
}

static void test_csv(void) {
  const char *text = "limit \"shoulder\", at 1\nknot";
  const char *want = "\"limit \"\"shoulder\"\", at 1 knot\"";
  char buf[256];
  FILE *fp = tmpfile();
  if (!fp) {
    ea_test_true(0, "tmpfile");
    return;
  }
  ea__csv_quote(fp, text);
  ea_test_true(!strcmp(captured(fp, buf, sizeof buf), want),
               "CSV field: quotes doubled, comma kept inside the quotes, line break a space");
  fclose(fp);
  ea__sbuf_t b = {0};
  ea__sbuf_csv_quote(&b, text);
  ea_test_true(!b.oom && !strcmp(b.s, want), "CSV field into a string buffer: the same bytes");
  ea__sbuf_free(&b);
  ea__sbuf_csv_quote(&b, NULL);
  ea_test_true(!b.oom && !strcmp(b.s, "\"\""), "CSV field of NULL is \"\"");
  ea__sbuf_free(&b);
}

static void test_json(void) {
  char buf[256];
  FILE *fp = tmpfile();
  if (!fp) {
    ea_test_true(0, "tmpfile");
    return;
  }
  ea_json_t j;
  ea_json_init(&j, fp, 0);
  ea_json_obj_begin(&j, NULL);
  ea_json_str(&j, "k", "a\"b\\c\nd\x01");
  ea_json_num(&j, "x", NAN);
  ea_json_obj_end(&j);
  ea_json_end(&j);
  ea_test_true(
      !strcmp(captured(fp, buf, sizeof buf), "{\"k\":\"a\\\"b\\\\c\\nd\\u0001\",\"x\":null}\n"),
      "JSON: quote, backslash, newline and control characters escaped; NaN is null");
  fclose(fp);
}

static void test_ext(void) {
  char out[64];
  ea__replace_ext("out/plan.csv", ".json", out, sizeof out);
  ea_test_true(!strcmp(out, "out/plan.json"), "extension replaced");
  ea__replace_ext("out.v1/plan", ".json", out, sizeof out);
  ea_test_true(!strcmp(out, "out.v1/plan.json"), "a dot in a folder name is not an extension");
  ea__replace_ext("a.tar.gz", "", out, sizeof out);
  ea_test_true(!strcmp(out, "a.tar"), "only the last extension removed");
}

static void test_clock(void) {
  const int64_t a = ea__mono_ns();
  const double s = ea__mono_s();
  const int64_t b = ea__mono_ns();
  ea_test_true(b >= a && s * 1e9 >= (double)a - 1e3 && s * 1e9 <= (double)b + 1e3,
               "monotonic clock: ns and s readings in order");
}

int main(void) {
  test_crc();
  test_csv();
  test_json();
  test_ext();
  test_clock();
  return ea_test_summary("test_util");
}
