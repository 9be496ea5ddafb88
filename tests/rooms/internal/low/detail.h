// kept to its room
