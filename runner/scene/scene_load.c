/*
 * scene_load.c - scene_load (scene.h): the file checked before libyaml
 * sees it, then read with libyaml's document API, its sections walked, its
 * sweep read (scene_sweep.c) and its keys checked (scene_parse.c) against
 * the key table (scene.c).
 *
 * The checks before parsing: a regular file of at most SCENE_MAX_BYTES,
 * UTF-8 text without NUL bytes, nested at most SCENE_MAX_DEPTH deep, with
 * no YAML tags but the core numeric ones (a tag changes what a value
 * means: `R: !!str 0.2`, `!!python/object/apply:...`).  Each refusal names
 * its place (LINE:COL, and the key for a tag) and says why; all of it
 * costs one pass over the text.
 */
#include "core/safeio.h"
#include "scene.h"
#include "scene_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

/* the largest scene file: the configs are a few kB, a scene with long
   sweep lists a few hundred */
#define SCENE_MAX_BYTES (1u << 20)

/* the deepest nesting of mappings and lists (a scene needs 3: section,
   key, value list); libyaml's time grows with the square of the depth */
#define SCENE_MAX_DEPTH 64

/* errors before any line: about the file */
static const scene_mark nowhere = {0, 0};

/* the file at path into *text (NUL-terminated) and *len: a regular file
   (not a FIFO, /dev/zero or a directory) of at most SCENE_MAX_BYTES,
   refused before it is read */
static int read_guarded(const char *path, char **text, size_t *len,
                        scene_error *err) {
  char why[200], size_rule[64];
  snprintf(size_rule, sizeof size_rule, "a scene is at most %u bytes (1 MiB)",
           (unsigned)SCENE_MAX_BYTES);
  if (file_read_all(path, SCENE_MAX_BYTES,
                    "a scene is a regular file (YAML text)", size_rule, text,
                    len, why, sizeof why) == 0)
    return 0;
  return scene_error_set(err, nowhere, "(file)", "%s", why);
}

/* the UTF-16 or UTF-32 encoding of a text, from its BOM or its NUL bytes
   (YAML 1.2, 5.2), or NULL */
static const char *wide_encoding(const unsigned char *t, size_t n) {
  if (n >= 4 && t[0] == 0 && t[1] == 0 && t[2] == 0xFE && t[3] == 0xFF)
    return "UTF-32 (big-endian)";
  if (n >= 4 && t[0] == 0xFF && t[1] == 0xFE && t[2] == 0 && t[3] == 0)
    return "UTF-32 (little-endian)";
  if (n >= 2 && t[0] == 0xFE && t[1] == 0xFF) return "UTF-16 (big-endian)";
  if (n >= 2 && t[0] == 0xFF && t[1] == 0xFE) return "UTF-16 (little-endian)";
  if (n >= 4 && t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] != 0)
    return "UTF-32 (big-endian)";
  if (n >= 4 && t[0] != 0 && t[1] == 0 && t[2] == 0 && t[3] == 0)
    return "UTF-32 (little-endian)";
  if (n >= 2 && t[0] == 0 && t[1] != 0) return "UTF-16 (big-endian)";
  if (n >= 2 && t[0] != 0 && t[1] == 0) return "UTF-16 (little-endian)";
  return NULL;
}

/* length of the valid UTF-8 sequence at t (n bytes left), or 0 (RFC 3629:
   no overlong forms, no surrogates, nothing above U+10FFFF) */
static size_t utf8_len(const unsigned char *t, size_t n) {
  unsigned c = t[0];
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) return n >= 2 && (t[1] & 0xC0) == 0x80 ? 2 : 0;
  if (c >= 0xE0 && c <= 0xEF) {
    unsigned lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
    return n >= 3 && t[1] >= lo && t[1] <= hi && (t[2] & 0xC0) == 0x80 ? 3 : 0;
  }
  if (c >= 0xF0 && c <= 0xF4) {
    unsigned lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
    return n >= 4 && t[1] >= lo && t[1] <= hi && (t[2] & 0xC0) == 0x80 &&
                   (t[3] & 0xC0) == 0x80
               ? 4
               : 0;
  }
  return 0;
}

/* NUL bytes and invalid UTF-8, at LINE:COL (columns in characters, as
   libyaml counts them) */
static int check_bytes(const unsigned char *t, size_t n, scene_error *err) {
  size_t i = 0;
  scene_mark at = {1, 1};
  while (i < n) {
    size_t k;
    if (t[i] == 0)
      return scene_error_set(err, at, "(file)",
                             "a NUL byte (byte %zu): not a text file", i);
    k = utf8_len(t + i, n - i);
    if (k == 0)
      return scene_error_set(
          err, at, "(file)",
          "invalid UTF-8 (byte %zu is 0x%02X): a scene is UTF-8 text", i, t[i]);
    if (t[i] == '\n' || (t[i] == '\r' && (i + 1 == n || t[i + 1] != '\n'))) {
      at.line++;
      at.column = 1;
    } else if (t[i] != '\r')
      at.column++;
    i += k;
  }
  return 0;
}

/* ---------------------------------------------------- the event pass */

/* one open mapping or sequence, and where its next node goes */
typedef struct {
  int is_map;
  int want_key; /* mapping: the next scalar is a key */
  char key[64]; /* mapping: the key of the value being read */
  size_t index; /* sequence: index of the next item */
} frame;

/* the dotted path of the node about to be read at depth d */
static void path_of(const frame *st, int d, char *out, size_t sz) {
  size_t len = 0;
  int i;
  out[0] = '\0';
  for (i = 0; i < d && len < sz; i++) {
    int w;
    if (i == 4) {
      /* deep enough to say where: the rest would fill the line */
      snprintf(out + len, sz - len, "...");
      break;
    }
    if (st[i].is_map)
      w = snprintf(out + len, sz - len, "%s%s", len ? "." : "", st[i].key);
    else
      w = snprintf(out + len, sz - len, "[%zu]", st[i].index);
    if (w < 0) break;
    len += (size_t)w;
  }
  if (!out[0]) snprintf(out, sz, "(root)");
}

/* a node has been read at depth d: move its parent on */
static void node_done(frame *st, int d) {
  if (d == 0) return;
  if (st[d - 1].is_map)
    st[d - 1].want_key = !st[d - 1].want_key;
  else
    st[d - 1].index++;
}

static int tag_allowed(const yaml_event_t *e) {
  const char *tag =
      e->type == YAML_SCALAR_EVENT ? (const char *)e->data.scalar.tag : NULL;
  return tag && (strcmp(tag, "tag:yaml.org,2002:int") == 0 ||
                 strcmp(tag, "tag:yaml.org,2002:float") == 0);
}

static const char *tag_of(const yaml_event_t *e) {
  const unsigned char *t =
      e->type == YAML_SCALAR_EVENT           ? e->data.scalar.tag
      : e->type == YAML_SEQUENCE_START_EVENT ? e->data.sequence_start.tag
      : e->type == YAML_MAPPING_START_EVENT  ? e->data.mapping_start.tag
                                             : NULL;
  return (const char *)t;
}

static int check_events(const char *text, size_t len, scene_error *err) {
  static const char core[] = "tag:yaml.org,2002:";
  yaml_parser_t p;
  frame st[SCENE_MAX_DEPTH];
  int d = 0, rc = 0, done = 0;
  if (!yaml_parser_initialize(&p)) return 0; /* scene_load says it */
  yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
  while (!done && rc == 0) {
    yaml_event_t e;
    char path[160];
    const char *tag;
    /* a syntax error is scene_load's to report, with its own words */
    if (!yaml_parser_parse(&p, &e)) break;
    tag = tag_of(&e);
    switch (e.type) {
    case YAML_STREAM_END_EVENT: done = 1; break;
    case YAML_SCALAR_EVENT:
    case YAML_SEQUENCE_START_EVENT:
    case YAML_MAPPING_START_EVENT:
      if (d > 0 && st[d - 1].is_map && st[d - 1].want_key) {
        /* a key: remember it for its value's path */
        if (e.type == YAML_SCALAR_EVENT)
          snprintf(st[d - 1].key, sizeof st[d - 1].key, "%s",
                   (const char *)e.data.scalar.value);
        else
          snprintf(st[d - 1].key, sizeof st[d - 1].key, "?");
      }
      if (tag && !tag_allowed(&e)) {
        /* as written: !!str for tag:yaml.org,2002:str */
        int is_core = strncmp(tag, core, sizeof core - 1) == 0;
        path_of(st, d, path, sizeof path);
        if (d > 0 && st[d - 1].is_map && st[d - 1].want_key)
          snprintf(path + strlen(path), sizeof path - strlen(path), "%s",
                   d > 1 ? " (a key)" : "(a key)");
        rc = scene_error_set(
            err, scene_mark_of(&e.start_mark), path,
            "YAML tag '%s%s' is not accepted: write the value plainly (only "
            "!!int and !!float may tag a number)",
            is_core ? "!!" : "", is_core ? tag + sizeof core - 1 : tag);
        break;
      }
      if (e.type == YAML_SCALAR_EVENT) {
        node_done(st, d);
        break;
      }
      if (d == SCENE_MAX_DEPTH) {
        path_of(st, d, path, sizeof path);
        rc = scene_error_set(err, scene_mark_of(&e.start_mark), path,
                             "nested more than %d levels deep: a scene needs 3",
                             SCENE_MAX_DEPTH);
        break;
      }
      memset(&st[d], 0, sizeof st[d]);
      st[d].is_map = e.type == YAML_MAPPING_START_EVENT;
      st[d].want_key = 1;
      d++;
      break;
    case YAML_SEQUENCE_END_EVENT:
    case YAML_MAPPING_END_EVENT:
      d--;
      node_done(st, d);
      break;
    case YAML_ALIAS_EVENT: node_done(st, d); break;
    default: break;
    }
    yaml_event_delete(&e);
  }
  yaml_parser_delete(&p);
  return rc;
}

/* UTF-16 and UTF-32 named as such (save as UTF-8), then the bytes and
   the events */
static int text_guard(const char *text, size_t len, scene_error *err) {
  const unsigned char *t = (const unsigned char *)text;
  const char *wide = wide_encoding(t, len);
  if (wide)
    return scene_error_set(
        err, nowhere, "(file)",
        "is %s text: save the scene as UTF-8 (e.g. iconv -f UTF-16 -t UTF-8)",
        wide);
  if (check_bytes(t, len, err)) return -1;
  return check_events(text, len, err);
}

/* the sections of document doc (its root mapping root) into s: their keys,
   the sweep, then the checks of the keys given; 0 or -1 with err set */
static int scene_parse_doc(scene *s, yaml_document_t *doc,
                           const yaml_node_t *root, scene_error *err) {
  scene_parse_ctx c;
  memset(&c, 0, sizeof c);
  c.ncase = 1;
  c.doc = doc;
  c.s = s;
  c.err = err;
  if (scene_walk_section(&c, root, "") ||
      (c.sweep_node != 0 &&
       scene_parse_sweep(&c, scene_node_get(&c, c.sweep_node))) ||
      scene_check_keys(&c))
    return -1;
  return 0;
}

int scene_load(scene *s, const char *path, scene_error *err) {
  yaml_parser_t parser;
  yaml_document_t doc, extra;
  yaml_node_t *root;
  int rc = -1;

  memset(s, 0, sizeof *s);
  memset(err, 0, sizeof *err);
  scene_values_default(&s->base);
  s->ncase = 1;
  s->file = strdup(path);
  if (!s->file)
    return scene_error_set(err, s->section[0], "(file)", "out of memory");
  if (read_guarded(path, &s->text, &s->text_len, err) ||
      text_guard(s->text, s->text_len, err))
    goto fail;

  if (!yaml_parser_initialize(&parser)) {
    scene_error_set(err, s->section[0], "yaml", "cannot initialise libyaml");
    goto fail;
  }
  yaml_parser_set_input_string(&parser, (const unsigned char *)s->text,
                               s->text_len);
  if (!yaml_parser_load(&parser, &doc)) {
    scene_error_set(err, scene_mark_of(&parser.problem_mark), "yaml", "%s%s%s",
                    parser.problem ? parser.problem : "syntax error",
                    parser.context ? " " : "",
                    parser.context ? parser.context : "");
    yaml_parser_delete(&parser);
    goto fail;
  }
  root = yaml_document_get_root_node(&doc);
  s->section[0].line = 1;
  s->section[0].column = 1;
  if (!root) {
    scene_error_set(err, s->section[0], "(root)", "empty scene");
  } else if (root->type != YAML_MAPPING_NODE) {
    scene_error_set(err, scene_mark_of(&root->start_mark), "(root)",
                    "expected a mapping of sections, got %s",
                    scene_node_kind(root));
  } else {
    /* a second document would be silently ignored: refuse it */
    if (!yaml_parser_load(&parser, &extra)) {
      scene_error_set(err, scene_mark_of(&parser.problem_mark), "yaml", "%s",
                      parser.problem ? parser.problem : "syntax error");
    } else {
      yaml_node_t *r2 = yaml_document_get_root_node(&extra);
      if (r2)
        scene_error_set(err, scene_mark_of(&r2->start_mark), "(root)",
                        "a second YAML document; a scene is one document");
      else {
        s->section[0] = scene_mark_of(&root->start_mark);
        rc = scene_parse_doc(s, &doc, root, err);
      }
      yaml_document_delete(&extra);
    }
  }
  yaml_document_delete(&doc);
  yaml_parser_delete(&parser);
  if (rc == 0) return 0;
fail:
  scene_free(s);
  return -1;
}
