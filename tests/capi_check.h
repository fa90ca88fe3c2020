/* CHECK(cond) for the C API's test programs: on failure, prints the file, line and condition, and
 * the library's last error message if there is one, then returns 1 from the calling function. */
#ifndef TOPOTET_TESTS_CAPI_CHECK_H
#define TOPOTET_TESTS_CAPI_CHECK_H

#include <stdio.h>

#include <topotet/topotet_c.h>

#define CHECK(cond)                                                                              \
  do {                                                                                           \
    if (!(cond)) {                                                                               \
      fprintf(stderr, "%s:%d: failed: %s\n", __FILE__, __LINE__, #cond);                         \
      if (topotet_last_error()[0]) fprintf(stderr, "  last error: %s\n", topotet_last_error()); \
      return 1;                                                                                  \
    }                                                                                            \
  } while (0)

#endif
