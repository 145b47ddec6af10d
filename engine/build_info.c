/* build_info.c — see build_info.h; values come from CMake compile definitions, the git
 * description from a header CMake regenerates at every build (engine/git_describe.cmake). */
#include "build_info.h"

#ifdef LUBDEM_GIT_FROM_HEADER
#include "lubdem_git.h"
#endif

#ifndef LUBDEM_VERSION
#define LUBDEM_VERSION "0.0.0"
#endif
#ifndef LUBDEM_GIT_DESCRIBE
#define LUBDEM_GIT_DESCRIBE "unknown"
#endif
#ifndef LUBDEM_COMPILER
#define LUBDEM_COMPILER "unknown"
#endif
#ifndef LUBDEM_CFLAGS
#define LUBDEM_CFLAGS ""
#endif

const char *lub_build_version(void) { return LUBDEM_VERSION; }
const char *lub_build_git(void) { return LUBDEM_GIT_DESCRIBE; }
const char *lub_build_compiler(void) { return LUBDEM_COMPILER; }
const char *lub_build_cflags(void) { return LUBDEM_CFLAGS; }
