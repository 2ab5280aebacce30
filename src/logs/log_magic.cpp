#include "logs/log_magic.h"

#include <cstdint>

#include "logs/crazyflie_usd.h"
#include "logs/dataflash.h"
#include "logs/dataflash_text.h"
#include "logs/ulog.h"

namespace quadfdi {

const char* logFormatOfMagic(ByteSpan head) {
  if (looksLikeUlog(head)) return "ulog";
  if (looksLikeDataflash(head) || looksLikeDataflashText(head)) return "dataflash";
  if (looksLikeCrazyflieUsd(head)) return "crazyflie";
  return nullptr;
}

bool looksBinary(ByteSpan bytes) {
  for (std::size_t i = 0; i < bytes.size; ++i)
    if (const std::uint8_t b = bytes.data[i]; b < 0x20 && b != '\t' && b != '\n' && b != '\r') return true;
  return false;
}

}  // namespace quadfdi
