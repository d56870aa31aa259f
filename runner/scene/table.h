/*
 * table.h - a table of samples for the trajectory kind `table` (the pose)
 * and the path shape `table` (the platform centre), read from a CSV or an
 * HDF5 file.  The library gets the arrays (rps3_table); the runner owns
 * them, reads them once per scene, and derives the rates a file lacks with
 * rps3_table_spline().
 *
 * CSV: '#' starts a comment line; the first other line names the columns,
 * the next lines hold one row of numbers each (strtod's, of any length),
 * comma separated; a line ends in LF, CR LF or CR.  HDF5: one 1-D dataset
 * of numbers per column at the file's root, all of one length, stored in
 * the file itself (no external link, external raw file or virtual
 * dataset).  The table is limited to TABLE_MAX_BYTES (table_int.h) as a
 * file, as declared and as held in memory.  Columns
 * (any order):
 *   pose    t, alpha, beta, z_c   [s, rad, rad, m]
 *   centre  t, x, y, z            [s, m, m, m]
 * optionally the rates NAME_dot of the three (all or none) and, with them,
 * the accelerations NAME_ddot.  A measured table (an identification's
 * data, scene/identify.h) has t, l1, l2, l3 [s, m], the rates l1_dot ..
 * [m/s], the accelerations l1_ddot .. [m/s^2] and the forces F1, F2, F3
 * [N], all required.  A CSV header may give a column's units in brackets
 * (l1 [m]), an HDF5 dataset a units attribute: either must name the
 * column's SI unit.
 */
#ifndef RPS3_RUNNER_TABLE_H
#define RPS3_RUNNER_TABLE_H

#include <stddef.h>

#include "rps3.h"

typedef struct {
  char *path;         /* as opened: the scene's directory and the name */
  char *abs;          /* absolute path (the resolved scene), or = path */
  int hdf5;           /* 1: read as HDF5, 0: as CSV */
  size_t n;           /* rows */
  double *time;       /* n times [s] */
  double (*value)[3]; /* n poses or centres */
  double (*rate)[3];  /* n rates: the file's, or the spline's */
  double (*acc)[3];   /* n accelerations, or NULL */
  int rates_given;    /* 1: the rates are the file's */
  int *line;          /* CSV: the line of each row; NULL for HDF5 */
  int what;           /* TABLE_POSE, TABLE_CENTRE or TABLE_MEASURED */
  double (*force)[3]; /* a measured table's n forces [N], else NULL */
} table_data;

/* which columns a table holds */
enum { TABLE_POSE = 0, TABLE_CENTRE = 1, TABLE_MEASURED = 2 };

/* the columns: 0 time, 1-3 values, 4-6 rates, 7-9 accelerations, 10-12 a
   measured table's forces; their names for TABLE_POSE, TABLE_CENTRE and
   TABLE_MEASURED (the first table_ncol(what)) */
#define TABLE_NCOL 13
extern const char *const table_col_names[3][TABLE_NCOL];

/* the columns of a table of `what`: 13 measured, else 10 */
int table_ncol(int what);

/*
 * Read the table `name` (relative to the directory of scene_file unless
 * absolute; HDF5 when it ends in .h5 or .hdf5, else CSV) with the columns
 * of `what` (TABLE_POSE, TABLE_CENTRE or TABLE_MEASURED) into t.  Returns 0, or
 * -1 with "FILE:LINE:COL: column NAME: what is wrong" ("FILE: dataset /NAME:
 * ..." or "FILE, row R: dataset /NAME: ..." for HDF5) in err, printable text (a
 * quoted control character or non-UTF-8 byte as \xNN); t is then empty
 * (table_free accepts it).
 */
int table_read(table_data *t, const char *scene_file, const char *name,
               int what, char *err, size_t errsz);

/* Free what table_read allocated; a zeroed table is accepted. */
void table_free(table_data *t);

/* "FILE:LINE" of row r (CSV) or "FILE, row R" (HDF5), into buf */
void table_where(const table_data *t, size_t r, char *buf, size_t sz);

/* The library's view of t (arrays not copied). */
rps3_table table_view(const table_data *t);

#endif /* RPS3_RUNNER_TABLE_H */
