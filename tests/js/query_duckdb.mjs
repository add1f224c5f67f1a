// Runs one SQL query in an in-memory DuckDB and prints its rows as a JSON array (INT64 values as
// decimal strings, as read_parquet.mjs prints them). The dataset tests use it for what needs a
// glob over many files, e.g. read_parquet('ROOT/data/*/*.parquet'), as LeRobot reads them.
//   node query_duckdb.mjs 'SELECT ...'
import { DuckDBInstance } from '@duckdb/node-api';
import { plain } from './plain_json.mjs';

const sql = process.argv[2];
if (!sql) {
  console.error("usage: node query_duckdb.mjs 'SELECT ...'");
  process.exit(2);
}

const instance = await DuckDBInstance.create(':memory:');
const connection = await instance.connect();
const rows = (await connection.runAndReadAll(sql)).getRowObjectsJS();
connection.closeSync();
instance.closeSync();
process.stdout.write(JSON.stringify(plain(rows)));
