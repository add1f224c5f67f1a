// Writes a Parquet file with DuckDB, a writer we did not write, for the reader's tests:
//   node write_parquet.mjs OUT.parquet ROWS PARQUET_VERSION(v1|v2) [ROW_GROUP_SIZE [COMPRESSION]]
// The table (row i = 0..ROWS-1):
//   id      BIGINT   i * 1000003 - 5
//   small   BIGINT   i % 3                (low cardinality: dictionary encoded)
//   half    REAL     i / 2 + 0.1          (float32)
//   third   DOUBLE   i / 3
//   label   VARCHAR  'task ' || (i % 4)   (dictionary encoded)
//   name    VARCHAR  'row-' || i          (one value per row)
//   vec     REAL[]   [i, i + 0.5, -i] when i % 5 != 0, else [] (varying length)
// COMPRESSION is snappy unless given (zstd, uncompressed, or gzip, which our reader rejects by name).
import { DuckDBInstance } from '@duckdb/node-api';

const [file, rowsText, version, rowGroupText, compression = 'snappy'] = process.argv.slice(2);
if (!file || !rowsText || !version) {
  console.error('usage: node write_parquet.mjs OUT.parquet ROWS v1|v2 [ROW_GROUP_SIZE [COMPRESSION]]');
  process.exit(2);
}
const rows = Number(rowsText);
const rowGroupSize = Number(rowGroupText) > 0 ? `, ROW_GROUP_SIZE ${Number(rowGroupText)}` : '';
if (!/^[a-z0-9_]+$/.test(compression)) throw new Error(`bad compression ${compression}`);
const instance = await DuckDBInstance.create(':memory:');
const connection = await instance.connect();
await connection.run(`
  COPY (
    SELECT i::BIGINT * 1000003 - 5 AS id,
           (i % 3)::BIGINT AS small,
           (i / 2 + 0.1)::REAL AS half,
           (i / 3)::DOUBLE AS third,
           'task ' || (i % 4) AS label,
           'row-' || i AS name,
           CASE WHEN i % 5 = 0 THEN []::REAL[] ELSE [i::REAL, (i + 0.5)::REAL, (-i)::REAL] END AS vec
    FROM range(${rows}) AS t(i) ORDER BY i
  ) TO '${file.replaceAll("'", "''")}'
  (FORMAT parquet, COMPRESSION ${compression}, PARQUET_VERSION ${version}${rowGroupSize})`);
connection.closeSync();
instance.closeSync();
