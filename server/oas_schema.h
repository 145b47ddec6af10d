/* oas_schema.h — the OpenAPI 3.0 Schema Object form of a JSON Schema draft-07 schema, for the
 * per-input "schema" of a process description (OGC API - Processes 1.0 defines it as an
 * OpenAPI 3.0 Schema Object; schema/<scene>.schema.json are draft-07).
 *
 * Rules, applied at every level (properties, items, additionalProperties, not, allOf, anyOf,
 * oneOf):
 *  - a numeric exclusiveMinimum x becomes minimum x with exclusiveMinimum true; beside a minimum
 *    the tighter bound is kept (x >= minimum: exclusive at x, else inclusive at minimum); the
 *    same for exclusiveMaximum/maximum (x <= maximum: exclusive at x). A boolean exclusive flag
 *    (already the OpenAPI form) is kept as it is;
 *  - const v becomes enum [v] (an error beside an enum);
 *  - a type array [T, "null"] becomes type T with nullable true, [T] type T; an array of two or
 *    more types becomes anyOf of one {"type": T} each (with nullable true on each if "null" was
 *    in it), placed in allOf when the schema already has an anyOf; type "null" alone is an
 *    error (OpenAPI 3.0 has no null type);
 *  - an enum without a type is kept as it is (valid OpenAPI 3.0, whatever types it mixes);
 *  - if/then/else are dropped and a sentence is appended to the description (after ". "): the
 *    "description" of the "if" subschema (which the schema file writes to state the condition
 *    in words), or, without one, a generic sentence pointing at the process's draft-07
 *    inputsSchema;
 *  - $schema, $id and $comment are dropped;
 *  - a boolean schema (true, false) becomes {} or {"not": {}} (additionalProperties keeps its
 *    boolean);
 *  - the OpenAPI 3.0 keywords (title, description, default, enum, required, multipleOf, the
 *    length, item and property counts, pattern, uniqueItems, format, nullable, readOnly,
 *    writeOnly, example, deprecated, x-*) are copied;
 *  - any other keyword ($ref, definitions, contains, propertyNames, dependencies,
 *    patternProperties, additionalItems, examples, an items array, ...) is an error: the
 *    schema files use none, and a new one must be given a rule rather than be served as
 *    draft-07.
 *
 * Pure. Returns a new reference (a deep copy: it shares no value with `draft`, which is not
 * modified), or NULL with a message naming the JSON Pointer of the offending member in err
 * (errlen bytes, always terminated). */
#ifndef LUBD_OAS_SCHEMA_H
#define LUBD_OAS_SCHEMA_H

#include <stddef.h>

#include <jansson.h>

json_t *lubd_oas_schema(json_t *draft, char *err, size_t errlen);

#endif
