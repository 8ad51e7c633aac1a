/* Command streamer: transports (TCP, UDP, serial via termios, file) and the
 * sleep until a monotonic deadline (clock: model/util/clock.c). No printing; every failure is a
 * status with a message. */
#include "stream_impl.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

/* ---- Time ---------------------------------------------------------------- */

void ea__sleep_until_ns(int64_t t_ns, const volatile sig_atomic_t *stop) {
  struct timespec ts = {(time_t)(t_ns / 1000000000LL), (long)(t_ns % 1000000000LL)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
    if (stop && *stop) return;
}

static int ea__cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

double ea__quantile(double *v, int n, double q) {
  if (n <= 0) return NAN;
  qsort(v, (size_t)n, sizeof *v, ea__cmp_double);
  double r = q * (n - 1);
  int i = (int)floor(r);
  if (i >= n - 1) return v[n - 1];
  return v[i] + (r - i) * (v[i + 1] - v[i]);
}

/* ---- Addresses ------------------------------------------------------------- */

ea_status_t ea__split_hostport(const char *s, char *host, size_t hcap, int *port, ea_error_t *err) {
  const char *colon, *h = s;
  size_t hl;
  if (s[0] == '[') {
    const char *rb = strchr(s, ']');
    if (!rb || rb[1] != ':')
      return ea_error_set(err, EA_ERR_ARG, "'%s': expected [ADDRESS]:PORT", s);
    h = s + 1;
    hl = (size_t)(rb - h);
    colon = rb + 1;
  } else {
    colon = strrchr(s, ':');
    if (!colon) return ea_error_set(err, EA_ERR_ARG, "'%s': expected HOST:PORT", s);
    hl = (size_t)(colon - s);
  }
  if (hl == 0 || hl >= hcap) return ea_error_set(err, EA_ERR_ARG, "'%s': bad host", s);
  memcpy(host, h, hl);
  host[hl] = '\0';
  char *end;
  errno = 0;
  const long p = strtol(colon + 1, &end, 10);
  if (end == colon + 1 || *end || errno || p < 0 || p > 65535)
    return ea_error_set(err, EA_ERR_ARG, "'%s': port must be 0..65535", s);
  *port = (int)p;
  return EA_OK;
}

/* ---- Serial ----------------------------------------------------------------- */

unsigned ea__baud_constant(long bps) {
  switch (bps) {
  case 9600:
    return B9600;
  case 19200:
    return B19200;
  case 38400:
    return B38400;
  case 57600:
    return B57600;
  case 115200:
    return B115200;
  case 230400:
    return B230400;
#ifdef B460800
  case 460800:
    return B460800;
#endif
#ifdef B921600
  case 921600:
    return B921600;
#endif
#ifdef B1000000
  case 1000000:
    return B1000000;
#endif
#ifdef B2000000
  case 2000000:
    return B2000000;
#endif
#ifdef B3000000
  case 3000000:
    return B3000000;
#endif
#ifdef B4000000
  case 4000000:
    return B4000000;
#endif
  default:
    return 0;
  }
}

ea_status_t ea__serial_setup(int fd, long bps, ea_error_t *err) {
  const unsigned b = ea__baud_constant(bps);
  if (!b) return ea_error_set(err, EA_ERR_ARG, "serial: unsupported baud rate %ld", bps);
  struct termios tio;
  if (tcgetattr(fd, &tio) != 0)
    return ea_error_set(err, EA_ERR_NET, "serial: not a terminal device: %s", strerror(errno));
  cfmakeraw(&tio); /* 8 data bits, no parity, no echo, no line editing */
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(tcflag_t)(CSTOPB | PARENB);
#ifdef CRTSCTS
  tio.c_cflag &= ~(tcflag_t)CRTSCTS;
#endif
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (cfsetispeed(&tio, b) != 0 || cfsetospeed(&tio, b) != 0 || tcsetattr(fd, TCSANOW, &tio) != 0)
    return ea_error_set(err, EA_ERR_NET, "serial: cannot configure %ld baud: %s", bps,
                        strerror(errno));
  tcflush(fd, TCIOFLUSH);
  return EA_OK;
}

/* ---- Transports ----------------------------------------------------------------- */

static ea_status_t ea__connect(ea__transport_t *t, const char *hostport, int dgram,
                               ea_error_t *err) {
  char host[256], service[16];
  int port;
  ea_status_t st = ea__split_hostport(hostport, host, sizeof host, &port, err);
  if (st) return st;
  if (port == 0)
    return ea_error_set(err, EA_ERR_ARG, "'%s': port 0 is not a destination", hostport);
  snprintf(service, sizeof service, "%d", port);
  struct addrinfo hints, *res = NULL;
  memset(&hints, 0, sizeof hints);
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = dgram ? SOCK_DGRAM : SOCK_STREAM;
  const int gai = getaddrinfo(host, service, &hints, &res);
  if (gai) return ea_error_set(err, EA_ERR_NET, "%s: %s", hostport, gai_strerror(gai));
  int fd = -1, last_errno = 0;
  for (struct addrinfo *ai = res; ai; ai = ai->ai_next) {
    fd = socket(ai->ai_family, ai->ai_socktype | SOCK_CLOEXEC, ai->ai_protocol);
    if (fd < 0) {
      last_errno = errno;
      continue;
    }
    if (connect(fd, ai->ai_addr, ai->ai_addrlen) == 0) break;
    last_errno = errno;
    close(fd);
    fd = -1;
  }
  freeaddrinfo(res);
  if (fd < 0)
    return ea_error_set(err, EA_ERR_NET, "%s://%s: cannot connect: %s", dgram ? "udp" : "tcp",
                        hostport, strerror(last_errno));
  if (!dgram) {
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one); /* one frame, one segment */
  }
  /* A send that blocks this long means the peer stopped reading. */
  struct timeval tv = {0, 200000};
  setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
  t->fd = fd;
  return EA_OK;
}

int ea__url_is_dry_run(const char *url) {
  return url &&
         (!strncmp(url, "file:", 5) || !strncmp(url, "csv:", 4) || !strncmp(url, "ros-yaml:", 9));
}

ea_status_t ea__transport_open(ea__transport_t *t, const char *url, ea_error_t *err) {
  memset(t, 0, sizeof *t);
  t->fd = -1;
  if (!url) return ea_error_set(err, EA_ERR_ARG, "no destination");
  ea_status_t st;
  if (!strncmp(url, "tcp://", 6)) {
    t->kind = EA__TR_TCP;
    st = ea__connect(t, url + 6, 0, err);
  } else if (!strncmp(url, "udp://", 6)) {
    t->kind = EA__TR_UDP;
    st = ea__connect(t, url + 6, 1, err);
  } else if (!strncmp(url, "serial:", 7)) {
    t->kind = EA__TR_SERIAL;
    char dev[512];
    long bps = 921600;
    snprintf(dev, sizeof dev, "%s", url + 7);
    char *at = strrchr(dev, '@');
    if (at) {
      char *end;
      bps = strtol(at + 1, &end, 10);
      if (end == at + 1 || *end) return ea_error_set(err, EA_ERR_ARG, "'%s': bad baud rate", url);
      *at = '\0';
    }
    if (!dev[0]) return ea_error_set(err, EA_ERR_ARG, "'%s': no device", url);
    t->fd = open(dev, O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (t->fd < 0) return ea_error_set(err, EA_ERR_NET, "%s: %s", dev, strerror(errno));
    st = ea__serial_setup(t->fd, bps, err);
    if (st) {
      close(t->fd);
      t->fd = -1;
    }
  } else if (ea__url_is_dry_run(url)) {
    const char *colon = strchr(url, ':');
    t->kind = !strncmp(url, "file:", 5)  ? EA__TR_FILE
              : !strncmp(url, "csv:", 4) ? EA__TR_CSV
                                         : EA__TR_ROS;
    if (!colon[1]) return ea_error_set(err, EA_ERR_ARG, "'%s': no path", url);
    st = ea_afile_open(&t->file, colon + 1, err);
  } else {
    return ea_error_set(err, EA_ERR_ARG,
                        "'%s': expected tcp://HOST:PORT, udp://HOST:PORT, serial:DEVICE[@BAUD], "
                        "file:PATH, csv:PATH or ros-yaml:PATH",
                        url);
  }
  if (st == EA_OK) t->is_open = 1;
  return st;
}

ea_status_t ea__transport_send(ea__transport_t *t, const uint8_t *buf, size_t len,
                               ea_error_t *err) {
  if (!t->is_open) return ea_error_set(err, EA_ERR_NET, "transport closed");
  if (t->kind == EA__TR_CSV || t->kind == EA__TR_ROS) return ea__export_frame(t, buf, len, err);
  if (t->kind == EA__TR_FILE) {
    if (fwrite(buf, 1, len, t->file.fp) != len)
      return ea_error_set(err, EA_ERR_IO, "write: %s", strerror(errno));
    return EA_OK;
  }
  size_t off = 0;
  while (off < len) {
    ssize_t k = (t->kind == EA__TR_SERIAL) ? write(t->fd, buf + off, len - off)
                                           : send(t->fd, buf + off, len - off, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0 && t->kind == EA__TR_UDP && errno == ECONNREFUSED)
      return ea_error_set(err, EA_ERR_NET, "udp: nobody listening (ICMP port unreachable)");
    if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
      return ea_error_set(err, EA_ERR_NET, "send blocked for 200 ms: peer not reading");
    if (k < 0) return ea_error_set(err, EA_ERR_NET, "send: %s", strerror(errno));
    if (t->kind == EA__TR_UDP && (size_t)k != len)
      return ea_error_set(err, EA_ERR_NET, "udp: short datagram");
    off += (size_t)k;
  }
  return EA_OK;
}

long ea__transport_recv(ea__transport_t *t, uint8_t *buf, size_t cap, int timeout_ms) {
  if (!t->is_open) return -1;
  if (EA__TR_IS_DRY(t->kind)) return 0;
  struct pollfd pf = {t->fd, POLLIN, 0};
  int r;
  do
    r = poll(&pf, 1, timeout_ms);
  while (r < 0 && errno == EINTR && timeout_ms == 0);
  if (r < 0) return errno == EINTR ? 0 : -1;
  if (r == 0) return 0;
  if (pf.revents & (POLLERR | POLLNVAL)) {
    if (t->kind == EA__TR_UDP) { /* ICMP unreachable: drain the error, report loss */
      int e = 0;
      socklen_t el = sizeof e;
      getsockopt(t->fd, SOL_SOCKET, SO_ERROR, &e, &el);
    }
    return -1;
  }
  ssize_t k = read(t->fd, buf, cap);
  if (k < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  if (k < 0) return -1;
  if (k == 0 && t->kind != EA__TR_UDP && t->kind != EA__TR_SERIAL) return -1; /* EOF */
  return (long)k;
}

ea_status_t ea__transport_close(ea__transport_t *t, int commit, ea_error_t *err) {
  ea_status_t st = EA_OK;
  if (!t->is_open) return EA_OK;
  if (EA__TR_IS_DRY(t->kind)) {
    if (commit)
      st = ea_afile_commit(&t->file, err);
    else
      ea_afile_abort(&t->file);
  } else if (t->fd >= 0) {
    if (t->kind == EA__TR_SERIAL) tcdrain(t->fd);
    close(t->fd);
  }
  t->fd = -1;
  t->is_open = 0;
  return st;
}
