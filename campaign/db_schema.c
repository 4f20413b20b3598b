/* db_schema: the schema and migrations of db/, embedded by the build. */
#include "db.h"

#include "db_sql.h"

const struct db_migration *db_migrations(int *n)
{
    *n = (int)(sizeof db_migrations_embedded / sizeof db_migrations_embedded[0]);
    return db_migrations_embedded;
}
