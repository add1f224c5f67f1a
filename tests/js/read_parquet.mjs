// Reads a Parquet file with two readers we did not write, hyparquet and DuckDB, and prints one
// JSON object: {"hyparquet": {...}, "duckdb": {...}}, each with the schema, the row count, the
// number of row groups, the key-value metadata, every row, and (DuckDB) the codecs of the column
// chunks. INT64 values (BigInt) are printed
// as decimal strings so that no digit is lost; floats as the numbers the readers return.
//   node read_parquet.mjs FILE.parquet
import { asyncBufferFromFile, parquetMetadataAsync, parquetReadObjects } from 'hyparquet';
import { DuckDBInstance } from '@duckdb/node-api';
import { plain } from './plain_json.mjs';

const file = process.argv[2];
if (!file) {
  console.error('usage: node read_parquet.mjs FILE.parquet');
  process.exit(2);
}

async function readWithHyparquet() {
  const buffer = await asyncBufferFromFile(file);
  const metadata = await parquetMetadataAsync(buffer);
  const rows = await parquetReadObjects({ file: buffer, metadata });
  return plain({
    schema: metadata.schema,
    num_rows: metadata.num_rows,
    num_row_groups: metadata.row_groups.length,
    key_value_metadata: metadata.key_value_metadata ?? [],
    created_by: metadata.created_by,
    rows,
  });
}

async function readWithDuckdb() {
  const instance = await DuckDBInstance.create(':memory:');
  const connection = await instance.connect();
  const quoted = `'${file.replaceAll("'", "''")}'`;
  const query = async (sql) => (await connection.runAndReadAll(sql)).getRowObjectsJS();
  const result = plain({
    schema: await query(`SELECT * EXCLUDE (file_name) FROM parquet_schema(${quoted})`),
    num_rows: (await query(`SELECT count(*) AS n FROM read_parquet(${quoted})`))[0].n,
    num_row_groups: (await query(`SELECT count(DISTINCT row_group_id) AS n FROM parquet_metadata(${quoted})`))[0].n,
    codecs: (await query(`SELECT DISTINCT compression FROM parquet_metadata(${quoted}) ORDER BY 1`)).map((row) => row.compression),
    key_value_metadata: await query(
      `SELECT decode(key) AS key, decode(value) AS value FROM parquet_kv_metadata(${quoted})`),
    rows: await query(`SELECT * FROM read_parquet(${quoted})`),
  });
  connection.closeSync();
  instance.closeSync();
  return result;
}

const output = { hyparquet: await readWithHyparquet(), duckdb: await readWithDuckdb() };
process.stdout.write(JSON.stringify(output));
