// libpq, blocking, on the sink's drain thread only. A failure that leaves the connection
// unusable (or whose state is unknown) drops it; the next write connects anew.
#include "sinks/postgres_writer.hpp"

#include <libpq-fe.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "rangekit/hub/sink_url.hpp"
#include "sinks/postgres_sql.hpp"

namespace rangekit::sinks {
namespace {

struct ResultFree {
  void operator()(PGresult* result) const { PQclear(result); }
};
using PgResult = std::unique_ptr<PGresult, ResultFree>;

// libpq's message in one line: its lines joined with "; ", spaces squeezed.
std::string one_line(const char* message) {
  std::string line;
  for (const char* at = message; at != nullptr && *at != '\0'; ++at) {
    const char c = *at == '\n' || *at == '\t' ? ' ' : *at;
    if (c == ' ' && (line.empty() || line.back() == ' ')) continue;
    if (*at == '\n' && at[1] != '\0') {
      line += "; ";
      continue;
    }
    line += c;
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  return line.empty() ? "no message from libpq" : line;
}

Result<std::string> read_password(const hub::SinkConfig& config) {
  if (!config.password_env.empty()) {
    const char* value = std::getenv(config.password_env.c_str());  // NOLINT(concurrency-mt-unsafe): nothing sets it
    if (value == nullptr) return make_error(Errc::io, "password_env: " + config.password_env + " is not set");
    return std::string(value);
  }
  if (config.password_file.empty()) return std::string();
  std::ifstream file(config.password_file, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  if (!file) return make_error(Errc::io, "password_file " + config.password_file + ": cannot be read");
  std::string password = text.str();
  if (!password.empty() && password.back() == '\n') password.pop_back();
  if (!password.empty() && password.back() == '\r') password.pop_back();
  if (password.empty()) return make_error(Errc::io, "password_file " + config.password_file + " is empty");
  return password;
}

class PostgresWriter final : public Writer {
 public:
  PostgresWriter(std::string url, std::string password, std::string table, std::chrono::milliseconds timeout)
      : url_(std::move(url)), password_(std::move(password)), table_(std::move(table)), timeout_(timeout) {}
  ~PostgresWriter() override { disconnect(); }
  PostgresWriter(const PostgresWriter&) = delete;
  PostgresWriter& operator=(const PostgresWriter&) = delete;

  WriteOutcome write(const std::vector<record::SpoolRow>& rows) override {
    if (connection_ == nullptr || PQstatus(connection_) != CONNECTION_OK) {
      if (auto ready = connect(); !ready) return failed(ready.error().message);
    }
    if (!staging_) {
      // A batch never sent before goes straight into the table, as psql's \copy does: a COPY
      // outside BEGIN is its own transaction, committed before it answers (no two more trips).
      WriteOutcome direct = copy_alone(rows);
      if (ran(direct) || state_ != "23505") return direct;
      staging_ = true;  // the table has some of these rows (a crash replay): they are skipped
    }
    std::size_t inserted = 0;
    WriteOutcome staged = transaction(rows, &inserted);
    if (ran(staged) && inserted == rows.size()) staging_ = false;  // past the repeats
    return staged;
  }

 private:
  static bool ran(const WriteOutcome& outcome) { return outcome.kind == WriteOutcome::Kind::confirmed; }

  // The rows by one COPY into the table, committed before it answers. An answer that is lost
  // is a failed write: the batch goes again and the table's key absorbs it.
  WriteOutcome copy_alone(const std::vector<record::SpoolRow>& rows) {
    state_.clear();
    const std::string sql = copy_into_table_sql(table_);
    PgResult copy(PQexec(connection_, sql.c_str()));
    if (PQresultStatus(copy.get()) != PGRES_COPY_IN && PQstatus(connection_) != CONNECTION_OK) {
      // An idle session the server ended (a restart) shows only now: once more, connected anew.
      if (auto ready = connect(); !ready) return failed(ready.error().message);
      copy.reset(PQexec(connection_, sql.c_str()));
    }
    if (PQresultStatus(copy.get()) != PGRES_COPY_IN) return outcome_of(copy.get());
    return send_copy(rows);
  }

  // One transaction: the rows COPYed into the session's staging table, then moved into the
  // table skipping the keys it has (their count in `inserted`); confirmed once COMMIT succeeded.
  WriteOutcome transaction(const std::vector<record::SpoolRow>& rows, std::size_t* inserted) {
    state_.clear();
    auto begun = run("BEGIN");
    if (!ran(begun)) {
      // As in copy_alone: a session the server ended shows only now.
      if (auto ready = connect(); !ready) return failed(ready.error().message);
      if (begun = run("BEGIN"); !ran(begun)) return begun;
    }
    const PgResult copy(PQexec(connection_, copy_into_staging_sql().c_str()));
    if (PQresultStatus(copy.get()) != PGRES_COPY_IN) return outcome_of(copy.get());
    if (auto copied = send_copy(rows); !ran(copied)) return copied;
    const PgResult moved(PQexec(connection_, insert_from_staging_sql(table_).c_str()));
    if (PQresultStatus(moved.get()) != PGRES_COMMAND_OK) return outcome_of(moved.get());
    *inserted = std::strtoull(PQcmdTuples(moved.get()), nullptr, 10);
    return run("COMMIT");
  }

  // The COPY's data, in messages of copy_chunk_bytes rather than one per row (as psql sends
  // a file), its end, and its result.
  WriteOutcome send_copy(const std::vector<record::SpoolRow>& rows) {
    const auto put = [&] {
      const bool sent = PQputCopyData(connection_, chunk_.data(), static_cast<int>(chunk_.size())) == 1;
      chunk_.clear();
      return sent;
    };
    chunk_.clear();
    bool sending = true;
    for (const record::SpoolRow& row : rows) {
      chunk_ += row.line;
      if (chunk_.size() >= copy_chunk_bytes && !(sending = put())) break;
    }
    if (sending && !chunk_.empty()) put();
    chunk_.clear();
    // The end is sent even after a refused PQputCopyData: its result then says why.
    PQputCopyEnd(connection_, nullptr);
    PgResult refusal;  // the first result that is no success; every result is read before the next command
    while (PGresult* each = PQgetResult(connection_)) {
      PgResult result(each);
      const ExecStatusType status = PQresultStatus(each);
      if (status == PGRES_COPY_IN || status == PGRES_COPY_OUT || status == PGRES_COPY_BOTH) {
        // The end did not get through: libpq would answer COPY_IN for ever.
        return failed("COPY did not end: " + one_line(PQerrorMessage(connection_)));
      }
      if (status != PGRES_COMMAND_OK && !refusal) refusal = std::move(result);
    }
    if (refusal) return outcome_of(refusal.get());
    return {WriteOutcome::Kind::confirmed, ""};
  }

  WriteOutcome failed(std::string why) {
    disconnect();
    return {WriteOutcome::Kind::failed, std::move(why)};
  }

  // SQLSTATE class 22 (data exception: a value PostgreSQL will never take) refuses the batch
  // for good; anything else fails it. The session is kept after those and after a repeated
  // key (23505, which write() answers), dropped after the rest: its state is not known.
  WriteOutcome outcome_of(const PGresult* result) {
    const char* state = PQresultErrorField(result, PG_DIAG_SQLSTATE);
    state_ = state != nullptr ? state : "";
    const std::string why =
        one_line(PQresultErrorMessage(result)[0] != '\0' ? PQresultErrorMessage(result) : PQerrorMessage(connection_));
    const bool data = state_.rfind("22", 0) == 0;
    if ((data || state_ == "23505") && PQstatus(connection_) == CONNECTION_OK) {
      // A COPY alone ended its own transaction; one in BEGIN is rolled back.
      if (PQtransactionStatus(connection_) != PQTRANS_IDLE) {
        const PgResult rolled_back(PQexec(connection_, "ROLLBACK"));
        if (PQresultStatus(rolled_back.get()) != PGRES_COMMAND_OK) disconnect();
      }
      return {data ? WriteOutcome::Kind::refused : WriteOutcome::Kind::failed, why};
    }
    return failed(state_.empty() ? why : why + " (SQLSTATE " + state_ + ")");
  }

  // One statement: confirmed when it ran, else what its error means.
  WriteOutcome run(const std::string& sql) {
    const PgResult result(PQexec(connection_, sql.c_str()));
    const ExecStatusType status = PQresultStatus(result.get());
    if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return {WriteOutcome::Kind::confirmed, ""};
    return outcome_of(result.get());
  }

  // One row's first column of a query, or empty; the error's outcome on failure.
  Result<std::string> first_value(const std::string& sql) {
    const PgResult result(PQexec(connection_, sql.c_str()));
    if (PQresultStatus(result.get()) != PGRES_TUPLES_OK) {
      return make_error(Errc::io, outcome_of(result.get()).why);
    }
    if (PQntuples(result.get()) == 0 || PQgetisnull(result.get(), 0, 0) != 0) return std::string();
    return std::string(PQgetvalue(result.get(), 0, 0));
  }

  Status connect() {
    disconnect();
    const std::string connect_timeout = std::to_string(std::max<long long>(2, (timeout_.count() + 999) / 1000));
    const std::string user_timeout = std::to_string(timeout_.count());
    // The URL first, expanded (expand_dbname): what follows overrides it.
    std::vector<const char*> keys{"dbname", "application_name", "connect_timeout", "tcp_user_timeout"};
    std::vector<const char*> values{url_.c_str(), "rangekit", connect_timeout.c_str(), user_timeout.c_str()};
    if (!password_.empty()) {
      keys.push_back("password");
      values.push_back(password_.c_str());
    }
    keys.push_back(nullptr);
    values.push_back(nullptr);
    connection_ = PQconnectdbParams(keys.data(), values.data(), 1);
    if (connection_ == nullptr) return make_error(Errc::io, "libpq could not allocate a connection");
    if (PQstatus(connection_) != CONNECTION_OK) {
      const std::string why = one_line(PQerrorMessage(connection_));
      disconnect();
      return make_error(Errc::io, why);
    }
    if (auto prepared = prepare(); !prepared) {
      disconnect();  // the next write makes sure of the tables again
      return prepared;
    }
    return ok_status();
  }

  // The table (created when missing, a hypertable where TimescaleDB is installed) and the
  // session's staging table. A statement that runs away is ended by the server.
  Status prepare() {
    const auto step = [&](const std::string& sql) -> Status {
      if (auto done = run(sql); !ran(done)) return make_error(Errc::io, done.why);
      return ok_status();
    };
    if (auto set = step("SET statement_timeout = " + std::to_string(statement_timeout_ms)); !set) return set;
    auto timescale = first_value("SELECT 1 FROM pg_extension WHERE extname = 'timescaledb'");
    if (!timescale) return std::move(timescale).error();
    auto missing = first_value("SELECT to_regclass('" + quote_identifier(table_) + "') IS NULL");
    if (!missing) return std::move(missing).error();
    if (*missing == "t") {
      const bool hypertable = !timescale->empty();
      if (auto begun = step("BEGIN"); !begun) return begun;
      if (auto made = step(create_table_sql(table_, hypertable)); !made) return made;
      if (hypertable) {
        if (auto made = first_value(create_hypertable_sql(table_)); !made) return std::move(made).error();
      }
      if (auto committed = step("COMMIT"); !committed) return committed;
    }
    return step(create_staging_sql());
  }

  void disconnect() {
    if (connection_ != nullptr) PQfinish(connection_);
    connection_ = nullptr;
  }

  static constexpr long long statement_timeout_ms = 60000;
  static constexpr std::size_t copy_chunk_bytes = std::size_t{64} * 1024;
  std::string chunk_;     // the COPY data message being filled
  bool staging_ = false;  // batches go through the staging table while they repeat rows
  std::string state_;     // the SQLSTATE of the last error
  std::string url_;
  std::string password_;
  std::string table_;
  std::chrono::milliseconds timeout_;
  PGconn* connection_ = nullptr;
};

}  // namespace

Result<std::unique_ptr<Writer>> open_postgres_writer(const SinkOptions& options) {
  const hub::SinkConfig& config = options.config;
  if (auto checked = hub::check_postgres_url(config.url); !checked) return std::move(checked).error();
  char* why = nullptr;
  PQconninfoOption* parsed = PQconninfoParse(config.url.c_str(), &why);
  if (parsed == nullptr) {
    const std::string message = why != nullptr ? one_line(why) : "out of memory";
    PQfreemem(why);
    return make_error(Errc::out_of_range, "url '" + hub::redacted_url(config.url) + "': " + message);
  }
  PQconninfoFree(parsed);
  if (!hub::valid_sql_identifier(config.table)) {
    return make_error(Errc::out_of_range, "table '" + config.table + "' is not an SQL identifier");
  }
  auto password = read_password(config);
  if (!password) return std::move(password).error();
  return std::unique_ptr<Writer>(
      std::make_unique<PostgresWriter>(config.url, std::move(*password), config.table, options.timeout));
}

}  // namespace rangekit::sinks
