/*
 * table_int.h - what the CSV reader (table.c), the HDF5 reader
 * (table_h5.c) and table_read.c share.
 */
#ifndef RPS3_RUNNER_TABLE_INT_H
#define RPS3_RUNNER_TABLE_INT_H

#include <stddef.h>

#include "table.h"

/* err = the formatted message; returns -1 (`return table_err(...)`) */
int table_err(char *err, size_t errsz, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* the largest table: its file (stat) and what it declares and holds in
   memory (rows times the bytes of a row); a million rows of ten numbers
   are ~80 MB */
#define TABLE_MAX_BYTES (1024.0 * 1024.0 * 1024.0)

/* why x cannot be a table's number ("is not a finite number", "is
   subnormal ..."; a subnormal loses precision), or NULL */
const char *table_bad_number(double x);

/* the arrays for n rows; acc only when the file has accelerations, line
   (the CSV line of each row) with with_line; refused above TABLE_MAX_BYTES
   in memory before anything is allocated: 0, or -1 with err set */
int table_alloc_rows(table_data *t, size_t n, int with_acc, int with_line,
                     char *err, size_t errsz);

/* where column c of row r goes */
double *table_cell(table_data *t, size_t r, int c);

/* which of the columns are present: t and the values always, the rates
   all or none, the accelerations all or none and only with the rates;
   named "column NAME" (CSV) or "dataset /NAME" (hdf5) */
int table_columns_check(const int have[TABLE_NCOL], int what, int hdf5,
                        const char *file, char *err, size_t errsz);

/* 1 when units (a CSV header's [UNITS], an HDF5 units attribute) name
   column c's SI unit in one of its spellings, or are empty;
   the unit's symbol */
int table_unit_ok(int what, int c, const char *units);
const char *table_unit_name(int what, int c);

/* path is a regular file of at most 1 GiB, checked by stat() before
   anything opens it: 0, or -1 with err set */
int table_regular_file(const char *path, char *err, size_t errsz);

/* the columns of `what` from the HDF5 file t->path into t: 0, or -1 */
int table_h5_read(table_data *t, int what, char *err, size_t errsz);

/* the rows of the CSV file t->path into t: 0, or -1 */
int table_csv_read(table_data *t, int what, char *err, size_t errsz);

#endif /* RPS3_RUNNER_TABLE_INT_H */
