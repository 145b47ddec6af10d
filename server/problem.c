/* problem.c — building RFC 7807 bodies. */
#include "problem.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "spec_reader.h"

int lubd_fail(lubd_fault *f, int status, const char *type, const char *title, const char *pointer,
              const char *fmt, ...)
{
    f->status = status;
    f->type = type;
    f->title = title;
    f->has_pointer = pointer != NULL;
    snprintf(f->pointer, sizeof f->pointer, "%s", pointer ? pointer : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(f->detail, sizeof f->detail, fmt, ap);
    va_end(ap);
    lub_utf8_trim_tail(f->pointer); /* where a long name was cut, keep it valid UTF-8 */
    lub_utf8_trim_tail(f->detail);
    f->retry_after = 0;
    return -1;
}

json_t *lubd_fault_json(const lubd_fault *f, const char *instance)
{
    json_t *o = json_object();
    json_object_set_new(o, "type", json_string(f->type ? f->type : "about:blank"));
    json_object_set_new(o, "title", json_string(f->title ? f->title : "Error"));
    json_object_set_new(o, "status", json_integer(f->status));
    /* detail may carry user bytes that are not UTF-8: json_stringn_nocheck is avoided. */
    json_t *d = json_string(f->detail);
    json_object_set_new(o, "detail", d ? d : json_string("(detail not valid UTF-8)"));
    if (instance) {
        json_t *i = json_string(instance);
        if (i)
            json_object_set_new(o, "instance", i);
    }
    if (f->has_pointer) {
        json_t *p = json_string(f->pointer);
        json_t *e = json_object();
        json_object_set_new(e, "pointer", p ? p : json_string(""));
        json_object_set(e, "detail", json_object_get(o, "detail"));
        json_object_set_new(o, "errors", json_pack("[o]", e));
    }
    return o;
}
