/*
 * info.h - the parts of `terrapatch info` (cmd_info.c) for a store (info_store.c) and an imagery
 * pyramid or light map (info_imagery.c).
 */
#ifndef TP_APP_INFO_H
#define TP_APP_INFO_H

/* `terrapatch info [--json] STORE.tpt` (info_store.c): called by tp_cli_info for a store. */
int tp_info_store(const char* path, int json);

/* `terrapatch info [--json] PYRAMID.tpi` (info_imagery.c): called by tp_cli_info for an
 * imagery pyramid; every block read and checked (exit 1 naming the first damaged one). */
int tp_info_imagery(const char* path, int json);
/* One line about the imagery pyramid (its path with .tpi) and one about the light map (.tpl)
 * beside a store, for each there is. */
void tp_info_imagery_beside(const char* store_path);

#endif /* TP_APP_INFO_H */
