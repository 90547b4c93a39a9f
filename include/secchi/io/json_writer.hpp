#pragma once
// A minimal streaming JSON writer for result files (objects, arrays, numbers, strings).
// Numbers are written with 17 significant digits so files compare bit for bit.
#include "secchi/core/config.hpp"
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

class JsonWriter {
public:
    explicit JsonWriter(std::ostream& os) : os_(os) {}

    JsonWriter& begin_object(const char* key = nullptr) { return open(key, '{'); }
    JsonWriter& end_object() { return close('}'); }
    JsonWriter& begin_array(const char* key = nullptr) { return open(key, '['); }
    JsonWriter& end_array() { return close(']'); }

    JsonWriter& value(const char* key, double v) {
        prefix(key);
        if (!std::isfinite(v)) {
            os_ << "null";
        } else {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.17g", v);
            os_ << buf;
        }
        return *this;
    }
    JsonWriter& value(const char* key, long long v) {
        prefix(key);
        os_ << v;
        return *this;
    }
    JsonWriter& value(const char* key, unsigned long long v) {
        prefix(key);
        os_ << v;
        return *this;
    }
    JsonWriter& value(const char* key, bool v) {
        prefix(key);
        os_ << (v ? "true" : "false");
        return *this;
    }
    JsonWriter& value(const char* key, const std::string& v) {
        prefix(key);
        os_ << '"';
        for (char ch : v) {
            if (ch == '"' || ch == '\\') os_ << '\\';
            os_ << ch;
        }
        os_ << '"';
        return *this;
    }
    JsonWriter& value(const char* key, const char* v) { return value(key, std::string(v)); }

private:
    JsonWriter& open(const char* key, char bracket) {
        prefix(key);
        os_ << bracket;
        first_.push_back(true);
        return *this;
    }
    JsonWriter& close(char bracket) {
        first_.pop_back();
        os_ << '\n' << std::string(2 * first_.size(), ' ') << bracket;
        if (first_.empty()) os_ << '\n';
        return *this;
    }
    void prefix(const char* key) {
        if (!first_.empty()) {
            if (!first_.back()) os_ << ',';
            first_.back() = false;
            os_ << '\n' << std::string(2 * first_.size(), ' ');
        }
        if (key) os_ << '"' << key << "\": ";
    }

    std::ostream& os_;
    std::vector<bool> first_;
};

}  // namespace secchi
