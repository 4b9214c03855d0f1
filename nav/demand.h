// DEMAND(condition): a check for our own bugs, always on. Bad input from outside is reported with exceptions
// or error results instead; DEMAND is for what can only be false if corridor itself is wrong. It sits in nav, the
// bottom of the tree, so that nav, drivers, face and server all use the same one.
#pragma once

#include <cstdio>
#include <cstdlib>

#define DEMAND(condition)                                                                                             \
  do {                                                                                                                \
    if (!(condition)) {                                                                                               \
      std::fprintf(stderr, "corridor: internal error: DEMAND(%s) failed at %s:%d\n", #condition, __FILE__, __LINE__); \
      std::abort();                                                                                                   \
    }                                                                                                                 \
  } while (false)
