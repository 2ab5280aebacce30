#include "logs/log_magic.h"

#include "logs/crazyflie_usd.h"
#include "logs/dataflash.h"
#include "logs/ulog.h"

namespace quadfdi {

const char* logFormatOfMagic(ByteSpan head) {
  if (looksLikeUlog(head)) return "ulog";
  if (looksLikeDataflash(head)) return "dataflash";
  if (looksLikeCrazyflieUsd(head)) return "crazyflie";
  return nullptr;
}

}  // namespace quadfdi
