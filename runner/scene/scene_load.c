/*
 * scene_load.c - scene_load (scene.h): the file checked before libyaml
 * sees it (scene_guard.h), read with libyaml's document API, then its
 * sections walked (scene_parse.c), its sweep read and its keys checked
 * (scene_sweep.c) against the key table (scene.c).
 */
#include "scene.h"
#include "scene_guard.h"
#include "scene_int.h"

#include <stdlib.h>
#include <string.h>

#include <yaml.h>

/* the file, checked before libyaml sees it (scene_guard.h) */
static int read_file(scene *s, const char *path, scene_error *err) {
  if (scene_read_guarded(path, &s->text, &s->text_len, err)) return -1;
  return scene_text_guard(s->text, s->text_len, err);
}

int scene_load(scene *s, const char *path, scene_error *err) {
  yaml_parser_t parser;
  yaml_document_t doc, extra;
  yaml_node_t *root;
  parse_ctx c;
  int rc = -1;

  memset(s, 0, sizeof *s);
  memset(err, 0, sizeof *err);
  scene_values_default(&s->base);
  s->ncase = 1;
  s->file = malloc(strlen(path) + 1);
  if (!s->file) {
    scene_error_set(err, s->section[0], "(file)", "out of memory");
    return -1;
  }
  strcpy(s->file, path);
  if (read_file(s, path, err)) goto fail;

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
  memset(&c, 0, sizeof c);
  c.ncase = 1;
  c.doc = &doc;
  c.s = s;
  c.err = err;
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
        if (scene_walk_section(&c, root, "") == 0 &&
            (c.sweep_node == 0 ||
             scene_parse_sweep(&c, scene_node_get(&c, c.sweep_node)) == 0) &&
            scene_check_keys(&c) == 0)
          rc = 0;
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
