typedef int ea__problems_placeholder;
