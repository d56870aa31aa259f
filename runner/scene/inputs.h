/*
 * inputs.h - the files a scene reads besides itself (the tables of its
 * KEY_FILE keys, scene.h), each with the SHA-256 of its content, so that
 * the parts of one run and a part kept by --resume are known to come from
 * the same data and not only from the same scene text.
 *
 * An output file records them in its root attribute input_files
 * (INPUTS_ATTR): one line a file, "KEY sha256:HEX PATH" (the dotted key,
 * 64 hexadecimal digits, the absolute path as read), in the order of the
 * key table; "" when the scene reads no file.  Two records are the same
 * run's when every key has the same digest: the paths are for the reader
 * (the same table may lie at another path on another host).
 */
#ifndef RPS3_RUNNER_INPUTS_H
#define RPS3_RUNNER_INPUTS_H

#include <stddef.h>

#include "scene.h"

/* the root attribute of an output file that holds the record */
#define INPUTS_ATTR "input_files"

/* hexadecimal SHA-256 and its terminating NUL */
#define INPUTS_HEX 65

/*
 * The SHA-256 of the content of the file at path, as 64 lowercase
 * hexadecimal digits into hex.  Returns 0, or -1 with err naming the file
 * and the cause.
 */
int inputs_sha256(const char *path, char hex[INPUTS_HEX], char *err,
                  size_t errsz);

/*
 * The record of the files the loaded scene s read (malloc'd, "" when
 * none).  Returns NULL with err set when a file cannot be read again, no
 * longer gives the rows the scene read (changed since), or a file key of
 * the key table is not known here.
 */
char *inputs_record(const scene *s, char *err, size_t errsz);

/*
 * Compare two records a and b (NULL: not recorded, as in a file written
 * before records were kept).  Returns 0 when every key has the same
 * digest in both; else 1 with `key` (the first key that differs), `path`
 * (its path in a, else in b) and the two digests ("none" where a record
 * lacks the key, "not recorded" for NULL) filled, each NUL-terminated
 * within its size.
 */
int inputs_differ(const char *a, const char *b, char *key, size_t keysz,
                  char *path, size_t pathsz, char *da, char *db, size_t dsz);

/*
 * The digest field ("sha256:HEX") and path of key `key` in the record rec
 * into dig and path (each NUL-terminated within its size).  Returns 1, or
 * 0 when rec is NULL or has no such key.
 */
int inputs_find(const char *rec, const char *key, char *dig, size_t dsz,
                char *path, size_t pathsz);

#endif /* RPS3_RUNNER_INPUTS_H */
