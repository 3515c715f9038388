// Replaced by the ULS codec sources.
namespace rangekit::uls {}
