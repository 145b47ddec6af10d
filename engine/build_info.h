/* build_info.h — provenance strings baked in at build time (version, git, compiler, flags).
 * Returned strings are static and never NULL. */
#ifndef LUBDEM_BUILD_INFO_H
#define LUBDEM_BUILD_INFO_H

const char *lub_build_version(void);
const char *lub_build_git(void);
const char *lub_build_compiler(void);
const char *lub_build_cflags(void);

#endif
