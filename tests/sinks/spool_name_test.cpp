// A sink's spool file is named after its kind and URL, never with the URL's password: none on
// disk, and the same spool after the password changes.
#include <gtest/gtest.h>

#include "rangekit/sinks/sink.hpp"

namespace {

using rangekit::sinks::spool_file_name;

rangekit::hub::SinkConfig sink(const std::string& kind, const std::string& url) {
  rangekit::hub::SinkConfig config;
  config.kind = kind;
  config.url = url;
  return config;
}

TEST(SpoolName, IsTheKindAndTheUrlWithoutItsPassword) {
  EXPECT_EQ(spool_file_name(sink("influx", "http://127.0.0.1:8428/write")), "influx-127.0.0.1-8428-write.spool");
  EXPECT_EQ(spool_file_name(sink("postgres", "postgresql://u:secret@h:5432/db")), "postgres-u-h-5432-db.spool");
  EXPECT_EQ(spool_file_name(sink("postgres", "postgresql://u:other@h:5432/db")), "postgres-u-h-5432-db.spool");
  EXPECT_EQ(spool_file_name(sink("influx", "http://h:8086/write?db=plant&u=me&p=secret")).find("secret"),
            std::string::npos);
}

}  // namespace
