// A check the library and device tests share: a call must throw one kind of error, with a
// message that says what went wrong.
#pragma once
#include <gtest/gtest.h>

#include <optional>
#include <string>

namespace lava::test {

// The E that `call` throws, once its message was expected to hold `part`; nothing when it
// returns, which fails the test saying `returned`.
template <typename E, typename Call>
std::optional<E> expectThrowsWith(Call&& call, const std::string& part,
                                  const std::string& returned = "accepted") {
  try {
    call();
    ADD_FAILURE() << returned;
  } catch (const E& error) {
    EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
    return error;
  }
  return std::nullopt;
}

}  // namespace lava::test
